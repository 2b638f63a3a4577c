"""The rigid bed of a column or a slab from ``boundary.bed``: its wall law (the paper's
Coulomb friction (2.17a), no slip, or the material's own law at the bed's slip rate,
``physics/bed.py``) and the nonlocal fluidity's condition on it (g = 0 on a bed that does
not slide, else ``boundary.bed_fluidity``)."""

from __future__ import annotations

from dataclasses import dataclass

from granflow.config import Config
from granflow.fem.engine import read_on_walls
from granflow.fem.forms import FrictionWall, WallLaw
from granflow.geometry.mesh import BED
from granflow.physics import CoulombFriction, Rheology
from granflow.physics.bed import MaterialBed, NoSlip

COULOMB, NO_SLIP, MATERIAL = "coulomb", "no-slip", "material"


@dataclass(frozen=True)
class MaterialBedRecipe:
    """The material bed before the run's law exists (a frozen part of the flow's spec):
    the flow's terms make it of the law they are built with (``FrictionWall.on_law``),
    read on the bed from the adjacent triangle (a hysteretic state, a layer's share)."""

    eps_friction: float

    def for_law(self, law: Rheology) -> MaterialBed:
        return MaterialBed(read_on_walls(law), self.eps_friction)

    def drag_coefficient_sq(self, slip_sq: object, normal_stress: object,
                            ops: object = None) -> object:
        raise TypeError("the material bed is made of the run's law first (for_law)")


def bed_law(config: Config) -> WallLaw:
    """What the bed exerts along itself."""
    bnd, eps_f = config.boundary, config.numerics.eps_friction
    if bnd.bed == NO_SLIP:
        return NoSlip(bnd.penalty)
    if bnd.bed == MATERIAL:
        return MaterialBedRecipe(eps_f)
    return CoulombFriction(bnd.bed_friction_deg, eps_f)


def bed_wall(config: Config) -> FrictionWall:
    """The bed as a wall of the flow solver: its law and the normal penalty (2.7)."""
    return FrictionWall(BED, bed_law(config), config.boundary.normal_load)


def rough_bed(config: Config) -> str:
    """The label on which the nonlocal fluidity is 0: the bed when it does not slide or
    when ``boundary.bed_fluidity = "zero"``, else none (zero flux)."""
    bnd = config.boundary
    return BED if bnd.bed == NO_SLIP or bnd.bed_fluidity == "zero" else ""
