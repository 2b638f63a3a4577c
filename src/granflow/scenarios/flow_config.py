"""The flow solver's frozen parts resolved from a run's configuration, in one place for
every kind of problem (``fem/flow_factory.py`` builds the solver from them on each mesh).

A kind says only what its domain is (``Layout``: its Coulomb walls, a periodic layer, the
boundaries with u = 0, the symmetry axis, where a fluidity vanishes, the free surface);
the rest is read here: the law and density of the run's materials, gravity, the channel's
side walls, the surface tension, the coordinates and time scheme, the solver choice, and
the fields coupled to the flow, each from its own resolver (``COUPLED_FIELDS``, in the
order they are built: the share of layer material before the fluidity and the packing
that blend with it).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from granflow.config import Config
from granflow.fem.augmented_lagrangian import AugmentedLagrangianSpec
from granflow.fem.coupling import CouplingSpec
from granflow.fem.flow_spec import Discretisation, FlowSpec, SolverChoice, Terms
from granflow.fem.forms import FrictionWall
from granflow.fem.held_walls import HeldWallsSpec
from granflow.fem.linalg import direct_solver
from granflow.fem.material_share import MaterialShareSpec
from granflow.fem.measure import PLANE, Coordinates
from granflow.fem.mobilisation_field import MobilisationSpec
from granflow.fem.primal_dual import PrimalDualSpec
from granflow.physics import gravity_vector, gravity_vector_3d
from granflow.scenarios.fluidity import fluidity_specs
from granflow.scenarios.materials import MaterialLaw, RunMaterials, augmentation, build_side_walls
from granflow.scenarios.packing import packing_specs


@dataclass(frozen=True)
class Layout:
    """What a kind's domain tells the flow: its Coulomb walls, whether it is a periodic
    layer, the boundaries with u = 0 (``dirichlet``) and the symmetry axis (``axis``),
    where a nonlocal law's fluidity is 0 (``rough``), the free surface that may carry the
    numerical surface tension (``surface``), how a nonlocal law's g at t = 0 is made
    from its law (``initial_fluidity``; None: g = 0), and the regions where each velocity
    component (x, y, z) is held at 0 (``held``: walls normal to an axis, u.N = 0 strongly)."""

    coordinates: Coordinates = PLANE
    walls: tuple[FrictionWall, ...] = ()
    periodic: bool = False
    dirichlet: str = ""
    axis: str = ""
    rough: str = ""
    surface: str = ""
    initial_fluidity: Callable[[Any, Config], Any] | None = None
    held: tuple[str, ...] = ()


Resolver = Callable[[Config, RunMaterials, Layout], tuple[CouplingSpec, ...]]


def _material_share(config: Config, materials: RunMaterials,
                    layout: Layout) -> tuple[CouplingSpec, ...]:
    return (MaterialShareSpec(),) if materials.layer is not None else ()


def _mobilisation(config: Config, materials: RunMaterials,
                  layout: Layout) -> tuple[CouplingSpec, ...]:
    return (MobilisationSpec(),) if materials.hysteretic else ()


def _fluidity(config: Config, materials: RunMaterials,
              layout: Layout) -> tuple[CouplingSpec, ...]:
    return fluidity_specs(config, materials, rough=layout.rough,
                          initial=layout.initial_fluidity)


def _packing(config: Config, materials: RunMaterials,
             layout: Layout) -> tuple[CouplingSpec, ...]:
    return packing_specs(config, materials)


def _held_walls(config: Config, materials: RunMaterials,
                layout: Layout) -> tuple[CouplingSpec, ...]:
    return (HeldWallsSpec(),) if any(layout.held) else ()


def _augmented_lagrangian(config: Config, materials: RunMaterials,
                          layout: Layout) -> tuple[CouplingSpec, ...]:
    r = augmentation(config)
    return (AugmentedLagrangianSpec(r),) if r is not None else ()


def _primal_dual(config: Config, materials: RunMaterials,
                 layout: Layout) -> tuple[CouplingSpec, ...]:
    num = config.numerics
    wanted = num.linearization == "primal-dual" and num.method == "regularized"
    return (PrimalDualSpec(),) if wanted else ()


COUPLED_FIELDS: tuple[Resolver, ...] = (_material_share, _mobilisation, _fluidity, _packing,
                                        _augmented_lagrangian, _primal_dual, _held_walls)


def flow_spec(config: Config, materials: RunMaterials, layout: Layout) -> FlowSpec:
    """The flow solver's frozen parts for a run of ``config`` on ``layout``."""
    num, mat, st = config.numerics, config.material, config.surface_tension
    gravity = gravity_vector_3d if layout.coordinates.dimension == 3 else gravity_vector
    terms = Terms(body_force=gravity(mat.gravity, config.geometry.slope_deg),
                  walls=layout.walls, penalty=config.boundary.penalty,
                  # in 3D the channel's side walls are boundaries of the mesh (its walls)
                  side_walls=(build_side_walls(config) if layout.coordinates.dimension == 2
                              else None),
                  surface_tension_on=layout.surface if st.enabled else "")
    discretisation = Discretisation(layout.coordinates, layout.periodic, layout.dirichlet,
                                    layout.axis, config.time.scheme, layout.held)
    choice = SolverChoice(num.linearization, direct_solver(num.linear_solver),
                          num.initial_guess, num.anderson_depth)
    couplings = tuple(spec for resolve in COUPLED_FIELDS
                      for spec in resolve(config, materials, layout))
    return FlowSpec(MaterialLaw(materials, num.eps), terms, discretisation, choice, couplings)
