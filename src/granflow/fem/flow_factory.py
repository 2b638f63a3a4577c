"""The flow solver built from frozen parts (``fem/flow_spec.py``): the terms of (3.2), the
discretisation and the solver choice, each resolved once from a run's configuration
(``scenarios/flow_config.py``),
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
from typing import Any

import ngsolve as ngs

from granflow.fem.coupling import Coupling, CouplingSpec, Site
from granflow.fem.flow import FlowParts, FlowSolver
from granflow.fem.flow_spec import (
    Discretisation,
    FlowSpec,
    GivenLaw,
    LawRecipe,
    SolverChoice,
    Terms,
)
from granflow.fem.forms import (
    SurfaceTraction,
    ViscoplasticStress,
    fixed_point_forms,
    momentum_terms,
    residual_form,
)
from granflow.fem.nonlinear import FixedPointSystem, NonlinearSolver, ResidualSystem
from granflow.fem.spaces import taylor_hood, vector_p2
from granflow.fem.time_scheme import time_scheme
from granflow.physics.laws import LawFields

__all__ = ["Discretisation", "FlowSpec", "GivenLaw", "LawRecipe", "SolverChoice", "Terms",
           "build_couplings", "build_flow"]

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
    space = taylor_hood(mesh, periodic=disc.periodic, dirichlet=disc.dirichlet, axis=disc.axis,
                        held=disc.held)
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
    duals = tuple(d for c in couplings for d in c.corrections(parts))
    picard = FixedPointSystem(forms.iterate, forms.rhs, freedofs, choice.linear_solver,
                              constant=forms.constant,
                              correction=next((d.forms(space) for d in duals), None),
                              rhs_reads_iterate=forms.rhs_reads_iterate)
    newton = ResidualSystem(residual_form(space, terms, coords), freedofs, choice.linear_solver)
    nonlinear = NonlinearSolver(picard=picard, newton=newton, state=solution,
                                dual=next(iter(duals), None),
                                anderson_depth=choice.anderson_depth)
    return FlowSolver(parts, nonlinear)
