"""The rigid bed of a column or a slab from ``boundary.bed``: its wall law (the paper's
Coulomb friction (2.17a), no slip, or the material's own law at the bed's slip rate,
``physics/bed.py``) and the nonlocal fluidity's condition on it (g = 0 on a bed that does
not slide, else ``boundary.bed_fluidity``)."""

from __future__ import annotations

from granflow.config import Config
from granflow.fem.engine import read_on_walls
from granflow.fem.forms import FrictionWall, WallLaw
from granflow.geometry.mesh import BED
from granflow.physics import CoulombFriction, Rheology
from granflow.physics.bed import MaterialBed, NoSlip

COULOMB, NO_SLIP, MATERIAL = "coulomb", "no-slip", "material"


def bed_law(config: Config, law: Rheology) -> WallLaw:
    """What the bed exerts along itself; ``law`` is the run's law (the material bed's,
    read on the bed from the adjacent triangle)."""
    bnd, eps_f = config.boundary, config.numerics.eps_friction
    if bnd.bed == NO_SLIP:
        return NoSlip(bnd.penalty)
    if bnd.bed == MATERIAL:
        return MaterialBed(read_on_walls(law), eps_f)
    return CoulombFriction(bnd.bed_friction_deg, eps_f)


def bed_wall(config: Config, law: Rheology) -> FrictionWall:
    """The bed as a wall of the flow solver: its law and the normal penalty (2.7)."""
    return FrictionWall(BED, bed_law(config, law), config.boundary.normal_load)


def rough_bed(config: Config) -> str:
    """The label on which the nonlocal fluidity is 0: the bed when it does not slide or
    when ``boundary.bed_fluidity = "zero"``, else none (zero flux)."""
    bnd = config.boundary
    return BED if bnd.bed == NO_SLIP or bnd.bed_fluidity == "zero" else ""
