"""The flow solver built from frozen parts: the terms of (3.2), the discretisation and the
solver choice, each resolved once from a run's configuration (``scenarios/flow_spec.py``),
and the couplings (``fem/coupling.py``) that each configured field brings.

``build_flow(mesh, spec)`` makes, in this order: the couplings' fields on the mesh and,
from what they hand it, the law and the density; the Taylor-Hood spaces (periodic, with an
axis, in plane, r-z or any coordinates ``fem/measure.py`` gives) and the time scheme; the
terms, the stress as the couplings leave it and their own terms; the fixed-point and
Newton systems with the couplings' corrections; then ``FlowSolver`` binds the couplings.
On every mesh of a run (the first, each remesh, a restored checkpoint) the same spec
builds the same solver.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import ngsolve as ngs

from granflow.fem.coupling import Coupling, CouplingSpec, Site
from granflow.fem.flow import Density, FlowParts, FlowSolver
from granflow.fem.forms import (
    FrictionWall,
    SurfaceTraction,
    ViscoplasticStress,
    fixed_point_forms,
    momentum_terms,
    residual_form,
)
from granflow.fem.measure import PLANE, Coordinates
from granflow.fem.nonlinear import FixedPointSystem, NonlinearSolver, ResidualSystem
from granflow.fem.spaces import taylor_hood, vector_p2
from granflow.fem.time_scheme import time_scheme
from granflow.physics import Rheology, SideWallFriction
from granflow.physics.laws import LawFields

# The run's law and density from the fields the couplings hand it
LawRecipe = Callable[[LawFields], tuple[Rheology, Density]]


@dataclass(frozen=True)
class Terms:
    """What the terms of (3.2) are made of besides the law: gravity (in the bed frame,
    one component per coordinate), the Coulomb walls and their penalty, a channel's side
    walls, and the boundary carrying the numerical surface tension (3.8)."""

    body_force: tuple[float, ...]
    walls: tuple[FrictionWall, ...] = ()
    penalty: float = 0.0
    side_walls: SideWallFriction | None = None
    surface_tension_on: str = ""          # "" = none


@dataclass(frozen=True)
class Discretisation:
    """The spaces and the time scheme: a periodic layer, the boundaries with u = 0 and the
    symmetry axis (u_r = 0), the coordinates and the scheme of (3.2a)."""

    coordinates: Coordinates = PLANE
    periodic: bool = False
    dirichlet: str = ""
    axis: str = ""
    scheme: str = "implicit-euler"


@dataclass(frozen=True)
class SolverChoice:
    """How each step's nonlinear problem is solved: the linearisation ("picard", "newton",
    "hybrid", "primal-dual"), the sparse LU, the first iterate and Anderson mixing."""

    linearization: str = "picard"
    linear_solver: str = "umfpack"
    initial_guess: str = "previous"
    anderson_depth: int = 0


@dataclass(frozen=True)
class FlowSpec:
    """Everything ``build_flow`` needs, frozen: the law from its fields, the terms, the
    discretisation, the solver choice and the couplings' specs (in the order they are
    built: a later one may read the fields an earlier one hands the law)."""

    law: LawRecipe
    terms: Terms
    discretisation: Discretisation = Discretisation()
    solver: SolverChoice = SolverChoice()
    couplings: tuple[CouplingSpec, ...] = field(default=())


@dataclass(frozen=True)
class GivenLaw:
    """A law and density that read no coupled field (a test's, a script's)."""

    rheology: Rheology
    density: Density

    def __call__(self, fields: LawFields) -> tuple[Rheology, Density]:
        return self.rheology, self.density


def build_couplings(site: Site, specs: tuple[CouplingSpec, ...]
                    ) -> tuple[tuple[Coupling, ...], LawFields]:
    """Each coupling on the mesh, and the fields they hand the law."""
    fields: dict[str, Any] = {}
    built = []
    for spec in specs:
        coupling = spec.build(site, fields)
        fields |= coupling.law_fields()
        built.append(coupling)
    return tuple(built), LawFields(**fields)


def build_flow(mesh: ngs.Mesh, spec: FlowSpec) -> FlowSolver:
    """The flow solver of ``spec`` on ``mesh`` (module docstring)."""
    disc, choice, t = spec.discretisation, spec.solver, spec.terms
    coords = disc.coordinates
    couplings, fields = build_couplings(
        Site(mesh, coords, disc.periodic, choice.linear_solver), spec.couplings)
    rheology, density = spec.law(fields)
    space = taylor_hood(mesh, periodic=disc.periodic, dirichlet=disc.dirichlet, axis=disc.axis)
    solution = ngs.GridFunction(space)    # (u^{n+1,k}, p^{n+1,k})
    scheme = time_scheme(disc.scheme, space, density)
    mesh_velocity = ngs.GridFunction(vector_p2(mesh))
    # gamma of (2.11)/(3.8) at the vertices, on the boundary ``surface_tension_on``
    tension = ngs.GridFunction(ngs.H1(mesh, order=1))
    stress = functools.reduce(lambda s, c: c.stress(s, rheology), couplings,
                              ViscoplasticStress(rheology, coords))
    terms = momentum_terms(
        density=density, inertia=scheme.inertia(), mesh_velocity=mesh_velocity,
        rheology=rheology, body_force=t.body_force, walls=t.walls, penalty=t.penalty,
        surface_traction=SurfaceTraction(t.surface_tension_on, tension)
        if t.surface_tension_on else None,
        side_walls=t.side_walls, stress=stress, coords=coords)
    terms += [term for c in couplings for term in c.terms()]
    parts = FlowParts(mesh=mesh, space=space, solution=solution, scheme=scheme,
                      mesh_velocity=mesh_velocity, surface_tension=tension, rheology=rheology,
                      density=density, coordinates=coords, terms=terms, choice=choice,
                      couplings=couplings)
    freedofs = space.FreeDofs()
    forms = fixed_point_forms(space, terms, solution, coords)
    dual = next(iter(d for c in couplings for d in c.corrections(parts)), None)
    picard = FixedPointSystem(forms.iterate, forms.rhs, freedofs, choice.linear_solver,
                              constant=forms.constant,
                              correction=dual.forms(space) if dual is not None else None,
                              rhs_reads_iterate=forms.rhs_reads_iterate)
    newton = ResidualSystem(residual_form(space, terms, coords), freedofs, choice.linear_solver)
    nonlinear = NonlinearSolver(picard=picard, newton=newton, state=solution, dual=dual,
                                anderson_depth=choice.anderson_depth)
    return FlowSolver(parts, nonlinear)


def coupling_fields(couplings: tuple[Coupling, ...]) -> Mapping[str, Any]:
    """The fields a tuple of couplings hands the law, by name."""
    return {k: v for c in couplings for k, v in c.law_fields().items()}
