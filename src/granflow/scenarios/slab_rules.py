"""The slab (``scenarios/slab.py``) as the configuration sees it (``config/kinds.py``): its
cross-field rules, its keys without effect, the triangles of its structured mesh, its finer
levels in space, its layer. Engine-free."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from granflow.config.kinds import KindRules, register_rules
from granflow.scenarios.bed_rules import bed_inert_keys
from granflow.scenarios.column_geometry_rules import erodible as layer  # the one test

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config


def describe(c: Config) -> str:
    g = c.geometry
    on = f"a {g.erodible_thickness:g} m layer" if g.erodible_thickness else "the bed"
    return f"slab {g.height:g} m thick on {on} at {g.slope_deg:g} deg"


def problems(c: Config) -> Iterator[str]:
    """Cells no thicker than the slab, a mesh that does not move (the flow is uniform
    along the bed: nothing moves the free surface)."""
    g, m = c.geometry, c.mesh
    if m.size > g.height:
        yield f"mesh.size = {m.size!r} must not exceed geometry.height = {g.height!r}"
    if c.numerics.mesh_velocity != "fixed":
        yield (f"numerics.mesh_velocity = {c.numerics.mesh_velocity!r} is not available for "
               "geometry.kind = 'slab' (a flow uniform along the bed does not move its "
               "surface); use 'fixed'")
    if c.geometry.dimension == 3:
        yield ("geometry.dimension = 3 is not available for geometry.kind = 'slab' (a "
               "section's layer); use 2")


def inert_keys(c: Config) -> dict[str, str]:
    """The column's geometry, walls and remeshing, the periodic layer's initial state."""
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    column = "it describes a column, and geometry.kind = 'slab'"
    add("geometry.shape geometry.width geometry.front_angle_deg geometry.bed_length "
        "geometry.axisymmetric geometry.bed_profile geometry.bed_profile_file geometry.mass "
        "geometry.mass_file geometry.left_wall gate.enabled gate.speed_law gate.speed "
        "gate.tau gate.friction_deg boundary.wall_friction_deg mesh.cells_across "
        "mesh.remesh_quality mesh.failure_remesh_quality mesh.layer_ahead mesh.layer_aspect "
        "mesh.adaptive mesh.rest_coarsening mesh.layer_rest_coarsening mesh.flow_margin "
        "numerics.volume_correction numerics.mesh_penalty numerics.ale_extrapolation "
        "surface_tension.enabled surface_tension.delta surface_tension.gamma0 "
        "surface_tension.trigger_angle_deg surface_tension.release_angle_deg "
        "surface_tension.length", column)
    add("geometry.half_channel boundary.non_penetration", "it describes a 3D channel, "
        "and the slab runs in two dimensions")
    add("initial.shear_rate initial.plug_base initial.fluidity", "it sets the periodic "
        "layer's initial state; a slab starts as a block (g = 0) over a layer at rest")
    if not layer(c):
        add("mesh.layer_cells", "geometry.erodible_thickness = 0 (no layer under the slab)")
    if c.boundary.channel_width is None:
        add("boundary.side_wall_friction_deg", "boundary.channel_width = none (no side walls)")
    if c.boundary.bed == "no-slip" and c.boundary.channel_width is None:
        add("numerics.eps_friction", "boundary.bed = 'no-slip' and no side walls: no "
            "Coulomb friction")
    if c.boundary.bed == "no-slip":
        add("boundary.normal_load", "boundary.bed = 'no-slip': no friction loaded by it")
    if not c.time.stop_at_rest:
        add("time.rest_fraction time.rest_duration", "time.stop_at_rest = false")
    return out | bed_inert_keys(c)


def cells_up(c: Config) -> int:
    """Cells across the slab and the layer."""
    g, m = c.geometry, c.mesh
    return max(1, round(g.height / m.size)) + (m.layer_cells if layer(c) else 0)


def triangles(c: Config) -> tuple[float, float]:
    """Two triangles per cell of the structured mesh (no remeshing)."""
    g, m = c.geometry, c.mesh
    return 2.0 * (m.cells_x or max(2, round(g.length / m.size))) * cells_up(c), 0.0


def smallest_size(c: Config, room: float) -> float:
    """The mesh.size that keeps the strip under ``room`` triangles."""
    g, m = c.geometry, c.mesh
    if m.cells_x:
        return 2.0 * m.cells_x * g.height / room
    return math.sqrt(2.0 * g.length * g.height / room)


def refine_space(c: Config, factor: int) -> dict[str, Any]:
    """mesh.size over ``factor``, and ``factor`` times the cells across the layer."""
    out: dict[str, Any] = {"mesh.size": c.mesh.size / factor}
    if layer(c):
        out["mesh.layer_cells"] = c.mesh.layer_cells * factor
    return out


SLAB_RULES = register_rules(KindRules(
    name="slab", describe=describe, triangles=triangles, smallest_size=smallest_size,
    refine_space=refine_space, problems=problems, inert_keys=inert_keys, erodible_layer=layer,
    stops_at_rest=lambda c: c.time.stop_at_rest))
