"""The frozen values a flow solver is built from (``fem/flow_factory.py: build_flow``): the
law and density from the fields its couplings hand them, the terms' values, the
discretisation, the solver choice and the couplings' specs. Resolved once from a run's
configuration (``scenarios/flow_config.py``); nothing here depends on a mesh."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import ngsolve as ngs

from granflow.fem.coupling import CouplingSpec
from granflow.fem.forms import FrictionWall
from granflow.fem.measure import PLANE, Coordinates
from granflow.physics import Rheology, SideWallFriction
from granflow.physics.laws import LawFields

Density = float | ngs.CoefficientFunction   # kg/m^3: one material, or blended (two)

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
    symmetry axis (u_r = 0), the coordinates and the scheme of (3.2a), and the regions
    where each component of u (x, y, z) is held at 0 (``held``: u.N = 0 imposed strongly
    on walls normal to an axis, in place of the penalty)."""

    coordinates: Coordinates = PLANE
    periodic: bool = False
    dirichlet: str = ""
    axis: str = ""
    scheme: str = "implicit-euler"
    held: tuple[str, ...] = ()


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
