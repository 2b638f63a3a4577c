"""The periodic layer (plug flow, section 4) as the configuration sees it
(``config/kinds.py``): its cross-field rules, its keys without effect, the triangles of its
structured mesh and its finer levels in space. Engine-free."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from granflow.config.kinds import KindRules, register_rules
from granflow.scenarios.three_d_rules import layer_3d_problems, three_d_inert_keys, three_d_problems

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config

COLUMN_ONLY = "it applies to columns only"


def describe(c: Config) -> str:
    return f"periodic layer {c.geometry.length:g} x {c.geometry.height:g} m"


def problems(c: Config) -> Iterator[str]:
    """A mesh no coarser than the layer, a plug base inside it, a fixed or vertical mesh."""
    g, m = c.geometry, c.mesh
    side = min(g.length, g.height)
    if m.size > side:
        yield (f"mesh.size = {m.size!r} must not exceed "
               f"min(geometry.length, geometry.height) = {side!r}")
    if c.initial.plug_base >= g.height:
        yield (f"geometry.height = {g.height!r} must be greater than "
               f"initial.plug_base = {c.initial.plug_base!r}")
    if c.numerics.mesh_velocity in ("elastic", "lagrange"):
        yield (f"numerics.mesh_velocity = {c.numerics.mesh_velocity!r} is not available for "
               "geometry.kind = 'periodic-layer'; use 'fixed' or 'vertical'")
    yield from three_d_problems(c)
    yield from layer_3d_problems(c)


def inert_keys(c: Config) -> dict[str, str]:
    """The column's keys, the walls' and the surface's: none acts on a periodic layer."""
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    column = "it describes a column, and geometry.kind = 'periodic-layer'"
    add("geometry.shape geometry.width geometry.front_angle_deg geometry.erodible_thickness "
        "geometry.bed_length geometry.axisymmetric", column)
    add("initial.slab_speed", "it describes a slab, and geometry.kind = 'periodic-layer'")
    add("boundary.channel_width boundary.side_wall_friction_deg",
        "the periodic layer is infinitely wide (the plane shear of section 4)")
    add("boundary.bed boundary.bed_friction_deg boundary.wall_friction_deg boundary.penalty "
        "boundary.normal_load numerics.eps_friction boundary.bed_fluidity",
        "the periodic layer has a no-slip bed and no walls")
    add("mesh.remesh_quality mesh.failure_remesh_quality mesh.layer_cells mesh.layer_ahead "
        "mesh.layer_aspect mesh.adaptive mesh.rest_coarsening mesh.layer_rest_coarsening "
        "mesh.flow_margin "
        "numerics.volume_correction time.stop_at_rest time.rest_fraction "
        "time.rest_duration surface_tension.enabled surface_tension.delta "
        "surface_tension.gamma0 surface_tension.trigger_angle_deg "
        "surface_tension.release_angle_deg surface_tension.length mesh.cells_across",
        COLUMN_ONLY)
    if c.numerics.mesh_velocity == "fixed":
        add("numerics.mesh_penalty numerics.ale_extrapolation",
            "numerics.mesh_velocity = 'fixed' (the mesh does not move)")
    add("geometry.bed_profile geometry.bed_profile_file geometry.mass geometry.mass_file "
        "geometry.left_wall gate.enabled gate.speed_law gate.speed gate.tau gate.friction_deg",
        column)
    return out | three_d_inert_keys(c, column=False)


def triangles(c: Config) -> tuple[float, float]:
    """Two triangles per cell of the structured mesh (mesh.cells_x or length / size
    across, height / size up); no layer."""
    g, m = c.geometry, c.mesh
    return 2 * (m.cells_x or g.length / m.size) * (g.height / m.size), 0.0


def smallest_size(c: Config, room: float) -> float:
    """The mesh.size that gives the layer ``room`` triangles: 2 cells_x H / size, or
    2 L H / size^2."""
    g, m = c.geometry, c.mesh
    if m.cells_x:
        return 2 * m.cells_x * g.height / room
    return math.sqrt(2 * g.length * g.height / room)


def refine_space(c: Config, factor: int) -> dict[str, Any]:
    """mesh.size over ``factor``, and mesh.cells_x times it where it is set."""
    out: dict[str, Any] = {"mesh.size": c.mesh.size / factor}
    if c.mesh.cells_x is not None:
        out["mesh.cells_x"] = c.mesh.cells_x * factor
    return out


PERIODIC_LAYER_RULES = register_rules(KindRules(
    name="periodic-layer", describe=describe, triangles=triangles,
    smallest_size=smallest_size, refine_space=refine_space, problems=problems,
    inert_keys=inert_keys))
