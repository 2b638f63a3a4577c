"""A block preconditioner of the linear systems of (3.2) for GMRes, from NGSolve's own parts
(measured by benchmarks/three_d_krylov.py; granflow's runs use the direct solve):

- the velocity block: NGSolve's BDDC of a velocity-only form (inertia, the regularised
  law's viscous term at the iterate, the walls' Coulomb friction), with the vertex values
  as its coarse space (``taylor_hood_vertex_wirebasket``; with NGSolve's default for P2 in
  3D the coarse space is every degree of freedom: a direct solve);
- the pressure block, the inverse of the Schur complement as Cahouet and Chabard's sum:
  the pressure mass weighted by 2 / m (the term m Du : Dv is (m / 2) grad u : grad v on
  divergence-free fields) by its diagonal, plus the pressure Laplacian times dt / rho (the
  inertia's share) by BDDC, p = 0 on the free surface by a Robin term (dt / rho) p q / h
  (a Nitsche-like weight, no other value tried); "viscous" keeps the mass alone.

The convection by u - w stays out (the preconditioner is symmetric) and in the matrix
GMRes sees. BDDC cannot be built with the penalty (2.7) (its boundary blocks are
singular): the walls' u.N = 0 must be held by the space (``boundary.non_penetration =
"strong"``). Every part runs on a mesh distributed over MPI ranks.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import ngsolve as ngs

from granflow.fem.forms import (
    BackwardDifferenceInertia,
    CoulombWallFriction,
    Inertia,
    Symbols,
    Term,
    ViscoplasticStress,
)
from granflow.fem.measure import Coordinates
from granflow.fem.spaces import HELD_FLAGS
from granflow.geometry.labels import SURFACE

SCHURS = ("cahouet-chabard", "viscous")     # the pressure block (``pressure_forms``)
VELOCITY_BLOCK = (Inertia, BackwardDifferenceInertia, ViscoplasticStress, CoulombWallFriction)


@dataclass
class BlockPreconditioner:
    """The velocity block's BDDC and the pressure block's inverse (``pressure_forms``: the
    weighted mass by its diagonal, plus the inertia's pressure Laplacian by BDDC), on the
    Taylor-Hood space, assembled afresh at each ``update`` (the iterate moved)."""

    space: ngs.FESpace
    velocity_form: ngs.BilinearForm
    pressure_forms: tuple[ngs.BilinearForm, ...]
    viscosity: ngs.CoefficientFunction       # m at the iterate (what weights the pressure)

    def __post_init__(self) -> None:
        self._velocity = ngs.Preconditioner(self.velocity_form, "bddc")
        kinds = ("local", "bddc")
        self._pressure = [ngs.Preconditioner(form, kind)
                          for form, kind in zip(self.pressure_forms, kinds, strict=False)]

    def update(self) -> None:
        for form in (self.velocity_form, *self.pressure_forms):
            form.Assemble()

    def pressure_mat(self) -> ngs.BaseMatrix:
        """The pressure block: the sum of its parts' preconditioners."""
        pressure = self._pressure[0].mat
        for part in self._pressure[1:]:
            pressure = pressure + part.mat
        return pressure

    @property
    def mat(self) -> ngs.BaseMatrix:
        eu, ep = self.space.Embedding(0), self.space.Embedding(1)
        return eu @ self._velocity.mat @ eu.T + ep @ self.pressure_mat() @ ep.T


def taylor_hood_vertex_wirebasket(mesh: ngs.Mesh, **flags: object) -> ngs.FESpace:
    """granflow's Taylor-Hood space (``fem/spaces.py``) with BDDC's coarse space of the
    velocity its vertex values."""
    held = dict(zip(HELD_FLAGS, flags.pop("held", ()), strict=False))
    axis, periodic = flags.pop("axis", ""), flags.pop("periodic", False)
    extra = {k: v for k, v in ({"dirichletx": axis} | held).items() if v}
    velocity = ngs.VectorH1(mesh, order=2, dirichlet=flags.pop("dirichlet", ""),
                            wb_withedges=False, **extra)
    pressure = ngs.H1(mesh, order=1)
    if periodic:
        velocity, pressure = ngs.Periodic(velocity), ngs.Periodic(pressure)
    return velocity * pressure


def block_preconditioner(space: ngs.FESpace, terms: Sequence[Term], stress: ViscoplasticStress,
                         iterate: ngs.GridFunction, coords: Coordinates,
                         schur: str = SCHURS[0]) -> BlockPreconditioner:
    """The preconditioner's forms from the terms of (3.2) at ``iterate`` (module
    docstring): the velocity block's terms, and the pressure block's."""
    velocity, pressure = space.components
    u, v = velocity.TnT()
    u_lin, p_lin = iterate.components
    zero = ngs.CF(0.0)
    s = Symbols(u=u, p=zero, v=v, q=zero, u_lin=u_lin, p_lin=p_lin, coords=coords)
    a = ngs.BilinearForm(velocity)
    for term in terms:
        if isinstance(term, CoulombWallFriction) and getattr(term.wall.law, "mu", 1) == 0:
            continue          # a zero boundary block: BDDC would have to invert it
        if isinstance(term, VELOCITY_BLOCK) and (lhs := term.lhs(s, velocity.mesh)) is not None:
            a += lhs
    m = stress.viscosity(u_lin, p_lin)
    return BlockPreconditioner(space, a, pressure_forms(pressure, m, terms, coords, schur), m)


def pressure_forms(pressure: ngs.FESpace, m: ngs.CoefficientFunction, terms: Sequence[Term],
                   coords: Coordinates, schur: str) -> tuple[ngs.BilinearForm, ...]:
    """The Schur complement's inverse as a sum (Cahouet and Chabard): the pressure mass
    weighted by 2 / m (the term m Du : Dv is (m / 2) grad u : grad v on divergence-free
    fields), and, with ``schur`` = "cahouet-chabard", the pressure Laplacian times dt / rho
    (the inertia's share), with p = 0 on the free surface imposed by a Robin term
    (dt / rho) p q / h there (a Nitsche-like weight; no other value tried)."""
    p, q = pressure.TnT()
    mass = ngs.BilinearForm(pressure)
    mass += coords.dx(2.0 / m * p * q)
    if schur != "cahouet-chabard":
        return (mass,)
    inertia = next(t for t in terms if isinstance(t, (Inertia, BackwardDifferenceInertia)))
    scale = inertia.dt / inertia.density
    laplace = ngs.BilinearForm(pressure)
    laplace += coords.dx(scale * ngs.grad(p) * ngs.grad(q))
    laplace += scale / ngs.specialcf.mesh_size * p * q * ngs.ds(SURFACE)
    return (mass, laplace)
