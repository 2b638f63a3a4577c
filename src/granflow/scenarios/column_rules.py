"""The column collapse as the configuration sees it (``config/kinds.py``): its cross-field
rules, its keys without effect, the triangles its mesher makes, its finer levels in space,
and what a user's mass sets before validation. The geometry's own rules (bed profile, mass
polygon, gate) are in ``column_geometry_rules``. Engine-free: the configuration is checked
before any mesh exists."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from granflow.config.kinds import KindRules, register_rules
from granflow.scenarios.bed_rules import bed_inert_keys
from granflow.scenarios.column_geometry_rules import (
    erodible,
    geometry_inert_keys,
    geometry_problems,
    resolve_geometry,
)
from granflow.scenarios.three_d_rules import (
    column_3d_problems,
    three_d_inert_keys,
    three_d_problems,
)

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config

LAYER_KEYS = ("geometry.bed_length mesh.layer_cells mesh.layer_ahead mesh.layer_aspect "
              "mesh.layer_rest_coarsening")


def describe(c: Config) -> str:
    g = c.geometry
    shape = "cylinder" if g.axisymmetric else g.shape
    bed = f" on a {g.erodible_thickness:g} m layer" if g.erodible_thickness else ""
    return f"{shape} column {g.width:g} x {g.height:g} m{bed}"


def problems(c: Config) -> Iterator[str]:
    """What a column cannot be: its mesh size against its sides, the layer against the
    column, a mesh velocity that moves the free surface, an axisymmetric column's limits,
    a trapezoid with a top, and the geometry's own rules."""
    g, m = c.geometry, c.mesh
    side = min(g.width, g.height)
    if m.size > side:
        yield (f"mesh.size = {m.size!r} must not exceed "
               f"min(geometry.width, geometry.height) = {side!r}")
    if erodible(c) and g.bed_length <= g.width:
        yield (f"geometry.bed_length = {g.bed_length!r} must be greater than "
               f"geometry.width = {g.width!r} (the erodible layer must reach beyond the "
               "column)")
    if erodible(c) and 0 < m.layer_ahead < m.size:
        yield (f"mesh.layer_ahead = {m.layer_ahead!r} must be 0 (the whole layer meshed) "
               f"or at least mesh.size = {m.size!r} (the layer is lengthened by at least "
               "half of it at a time)")
    if g.erodible_thickness >= g.height:
        yield (f"geometry.erodible_thickness = {g.erodible_thickness!r} must be less than "
               f"geometry.height = {g.height!r}")
    if c.numerics.mesh_velocity in ("fixed", "vertical"):
        yield (f"numerics.mesh_velocity = {c.numerics.mesh_velocity!r} is not available for "
               "geometry.kind = 'column' (its free surface must move); "
               "use 'elastic' (3.6) or 'lagrange' (3.7)")
    yield from _axisymmetric_problems(c)
    yield from three_d_problems(c)
    yield from column_3d_problems(c)
    builtin = g.mass is None and g.mass_file is None     # (a user's mass: no shape)
    if (builtin and g.shape == "trapezoid"
            and front_run(g.height, g.front_angle_deg) >= g.width):
        yield (f"geometry.front_angle_deg = {g.front_angle_deg!r} is too shallow for this "
               "column: its top width, width - height / tan(front_angle), must be > 0")
    else:                                   # (the scene is built only from a valid shape)
        yield from geometry_problems(c)


def _axisymmetric_problems(c: Config) -> Iterator[str]:
    """What an axisymmetric column cannot have: a slope (no longer symmetric), a channel's
    side walls, the plane-strain-only augmented Lagrangian and primal-dual correction."""
    if not c.geometry.axisymmetric:
        return
    if c.geometry.slope_deg != 0:
        yield (f"geometry.slope_deg = {c.geometry.slope_deg!r} needs a plane-strain column: "
               "a cylinder on a slope is not axisymmetric (use geometry.axisymmetric = false)")
    if c.boundary.channel_width is not None:
        yield (f"boundary.channel_width = {c.boundary.channel_width!r}: side walls need a "
               "plane-strain channel, not an axisymmetric column")
    if c.numerics.method == "augmented-lagrangian":
        yield ("numerics.method = 'augmented-lagrangian' is plane strain only; use "
               "'regularized' with geometry.axisymmetric = true")
    if c.numerics.linearization == "primal-dual":
        yield ("numerics.linearization = 'primal-dual' is plane strain only (its dual "
               "correction is built on the 2 x 2 strain rate); use 'picard', 'newton' or "
               "'hybrid' with geometry.axisymmetric = true")


def inert_keys(c: Config) -> dict[str, str]:
    """The keys without effect on this column, with the reason."""
    g, t, st = c.geometry, c.time, c.surface_tension
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    add("geometry.length initial.shear_rate initial.plug_base mesh.cells_x",
        "it describes the periodic layer, and geometry.kind = 'column'")
    add("initial.slab_speed", "it describes a slab, and geometry.kind = 'column'")
    out |= bed_inert_keys(c)
    if g.axisymmetric:
        add("boundary.wall_friction_deg", "geometry.axisymmetric = true: x = 0 is the "
            "symmetry axis (u_r = 0, no friction), not a wall")
    if g.erodible_thickness == 0:
        add(LAYER_KEYS, "it describes the erodible layer, and geometry.erodible_thickness = 0")
    if not c.mesh.adaptive:
        add("mesh.rest_coarsening mesh.layer_rest_coarsening mesh.flow_margin",
            "mesh.adaptive = false (the mesh is uniform)")
    elif g.erodible_thickness == 0 and c.mesh.rest_coarsening == 1:
        add("mesh.adaptive mesh.flow_margin", "over a rigid bed with mesh.rest_coarsening "
            "= 1 the mesh keeps mesh.size everywhere: there is nothing to adapt")
    if c.boundary.channel_width is None:
        add("boundary.side_wall_friction_deg", "boundary.channel_width = none (no side walls)")
    if g.shape == "rectangle":
        add("geometry.front_angle_deg", "geometry.shape = 'rectangle' has a vertical front")
    if not st.enabled:
        add("surface_tension.delta surface_tension.gamma0 surface_tension.trigger_angle_deg "
            "surface_tension.release_angle_deg surface_tension.length",
            "surface_tension.enabled = false")
    if not t.stop_at_rest:
        add("time.rest_fraction time.rest_duration", "time.stop_at_rest = false")
    if c.material.rheology == "nonlocal":
        add("initial.fluidity", "a column starts at rest (g = 0); it sets a periodic layer's "
            "initial fluidity")
    return out | geometry_inert_keys(c) | three_d_inert_keys(c, column=True)


def triangles(c: Config) -> tuple[float, float]:
    """Triangles the mesher will make (bulk, erodible layer), from the areas and sizes (an
    equilateral triangle of side h has area 0.433 h^2; the layer has its own finer cells)."""
    g, m = c.geometry, c.mesh
    layer = 0.0
    if erodible(c):   # length x thickness over cells of (thickness / cells)^2 x aspect:
        # thickness divided last, so that a subnormal one gives inf, never 0 / 0
        layer = g.bed_length * m.layer_cells**2 / 0.433 / m.layer_aspect / g.erodible_thickness
    return bulk_area(c) / 0.433 / m.size / m.size, layer


def smallest_size(c: Config, room: float) -> float:
    """The mesh.size that gives the column ``room`` triangles."""
    return math.sqrt(bulk_area(c) / 0.433 / room)


def bulk_area(c: Config) -> float:
    """Area of the column (m^2): the rectangle, less the front's triangle of a trapezoid."""
    g = c.geometry
    run = front_run(g.height, g.front_angle_deg) if g.shape == "trapezoid" else 0
    return g.width * g.height - 0.5 * g.height * min(run, g.width)


def front_run(height: float, angle_deg: float) -> float:
    """Horizontal extent of a trapezoid's front (inf for an angle whose tangent is 0 in
    floating point, such as 5e-324 degrees)."""
    slope = math.tan(math.radians(angle_deg))
    return height / slope if slope > 0 else math.inf


def refine_space(c: Config, factor: int) -> dict[str, Any]:
    """A finer column: mesh.cells_across times ``factor`` where it sets the resolution, else
    mesh.size over it; an erodible layer gets ``factor`` times the mesh.layer_cells."""
    m = c.mesh
    out: dict[str, Any] = ({"mesh.cells_across": m.cells_across * factor}
                           if m.cells_across is not None else {"mesh.size": m.size / factor})
    if erodible(c):
        out["mesh.layer_cells"] = m.layer_cells * factor
    return out


def derived_size(c: Config) -> float | None:
    """The mesh.size that mesh.cells_across sets (cells across the smaller side)."""
    cells = c.mesh.cells_across
    return None if cells is None else min(c.geometry.width, c.geometry.height) / cells


COLUMN_RULES = register_rules(KindRules(
    name="column", describe=describe, triangles=triangles, smallest_size=smallest_size,
    refine_space=refine_space, problems=problems, inert_keys=inert_keys, erodible_layer=erodible,
    stops_at_rest=lambda c: c.time.stop_at_rest, prepare=resolve_geometry,
    derived_size=derived_size, file_keys=("geometry.bed_profile_file", "geometry.mass_file")))
