"""Taylor–Hood P2/P1 spaces (paper section 3.1)."""

from __future__ import annotations

import ngsolve as ngs

HELD_FLAGS = ("dirichletx", "dirichlety", "dirichletz")


def taylor_hood(mesh: ngs.Mesh, *, periodic: bool = False, dirichlet: str = "",
                axis: str = "", held: tuple[str, ...] = ()) -> ngs.FESpace:
    """P2 velocity x P1 pressure; ``dirichlet`` names regions with u = 0 (case (a) bed),
    ``axis`` the symmetry axis of an axisymmetric flow, where u_r = u_x = 0, ``held`` the
    regions where each component (x, y, z) of u is 0: walls normal to that axis, where
    u.N = 0 is imposed strongly."""
    flags: dict[str, object] = {"dirichletx": axis} if axis else {}
    flags |= {flag: regions for flag, regions in zip(HELD_FLAGS, held, strict=False) if regions}
    velocity = ngs.VectorH1(mesh, order=2, dirichlet=dirichlet, **flags)
    pressure = ngs.H1(mesh, order=1)
    if periodic:
        velocity, pressure = ngs.Periodic(velocity), ngs.Periodic(pressure)
    return velocity * pressure


def vector_p2(mesh: ngs.Mesh) -> ngs.FESpace:
    """Continuous P2 vector fields (mesh velocity, carried velocity)."""
    return ngs.VectorH1(mesh, order=2)
