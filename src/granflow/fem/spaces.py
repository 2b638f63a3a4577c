"""Taylor–Hood P2/P1 spaces (paper section 3.1)."""

from __future__ import annotations

import ngsolve as ngs


def taylor_hood(mesh: ngs.Mesh, *, periodic: bool = False, dirichlet: str = "",
                axis: str = "") -> ngs.FESpace:
    """P2 velocity x P1 pressure; ``dirichlet`` names regions with u = 0 (case (a) bed),
    ``axis`` the symmetry axis of an axisymmetric flow, where u_r = u_x = 0."""
    if axis:
        velocity = ngs.VectorH1(mesh, order=2, dirichlet=dirichlet, dirichletx=axis)
    else:
        velocity = ngs.VectorH1(mesh, order=2, dirichlet=dirichlet)
    pressure = ngs.H1(mesh, order=1)
    if periodic:
        velocity, pressure = ngs.Periodic(velocity), ngs.Periodic(pressure)
    return velocity * pressure


def vector_p2(mesh: ngs.Mesh) -> ngs.FESpace:
    """Continuous P2 vector fields (mesh velocity, carried velocity)."""
    return ngs.VectorH1(mesh, order=2)
