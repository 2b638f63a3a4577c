"""The configuration's rules for a column's geometry: the bed profile, the mass polygon, the
left wall, the gate (``geometry/scene.py`` reads and checks them); the sizes a user's mass
sets; the keys without effect."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from granflow.config.schema import ConfigError, Gate, Geometry
from granflow.geometry.scene import Scene, build_scene
from granflow.geometry.sources import GeometryError

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config


def erodible(c: Config) -> bool:
    """A column over an erodible layer (geometry.erodible_thickness > 0): the one test,
    registered as the column's ``KindRules.erodible_layer``."""
    return c.geometry.erodible_thickness > 0


def scene(c: Config) -> Scene:
    """The column's scene (raises ``GeometryError``)."""
    return build_scene(c.geometry, c.gate)


def geometry_problems(c: Config) -> Iterator[str]:
    """What a column's geometry cannot be: one line each, naming the key."""
    g = c.geometry
    profile = g.bed_profile is not None or g.bed_profile_file is not None
    if profile and g.slope_deg != 0:
        yield (f"geometry.slope_deg = {g.slope_deg!r} with a bed profile: the profile gives "
               "the slopes (gravity is vertical); set geometry.slope_deg = 0 and incline the "
               "profile")
        return
    if profile and erodible(c) and c.mesh.layer_aspect != 1:
        yield (f"mesh.layer_aspect = {c.mesh.layer_aspect!r} needs the level bed: the "
               "stretched layer cells follow z = 0 (remove geometry.bed_profile, or set "
               "mesh.layer_aspect = 1)")
    if profile and erodible(c) and c.mesh.layer_ahead > 0:
        yield (f"mesh.layer_ahead = {c.mesh.layer_ahead!r} needs the level bed (the layer is "
               "lengthened along z = 0); set mesh.layer_ahead = 0 with a bed profile")
    if c.gate.enabled and c.numerics.method == "augmented-lagrangian":
        yield ("gate.enabled = true needs numerics.method = 'regularized' (the gate's moving "
               "friction is a term of (3.2))")
    if c.gate.enabled and g.axisymmetric:   # CHANGELOG: its iterations, measured
        yield ("gate.enabled = true is for plane columns: on an axisymmetric cylinder (a "
               "lifted tube) the gate is not verified and the iteration (3.2) hardly "
               "converges; set gate.enabled = false")
    try:
        scene(c)
    except GeometryError as err:
        yield str(err)


def geometry_inert_keys(c: Config) -> dict[str, str]:
    """The geometry and gate keys that change nothing in a run of ``c``, with the reason."""
    g, gate = c.geometry, c.gate
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    gate_keys = "gate.speed_law gate.speed gate.tau gate.friction_deg"
    if g.mass is not None or g.mass_file is not None:
        add("geometry.shape geometry.front_angle_deg",
            "geometry.mass gives the mass (not a built-in shape)")
    if not gate.enabled:
        add(gate_keys, "gate.enabled = false (an instantaneous release)")
    elif gate.speed_law == "constant":
        add("gate.tau", "gate.speed_law = 'constant'")
    if g.axisymmetric:
        add("geometry.left_wall", "geometry.axisymmetric = true: x = 0 is the symmetry axis")
    return out


def resolve_geometry(data: dict[str, Any], base: dict[str, Any]) -> None:
    """Before validation (in place): a user's mass sets geometry.width and geometry.height
    (in ``base`` too: they are not the user's to set); a width or height the user set as
    well is refused."""
    geometry = data.get("geometry", {})
    if not isinstance(geometry, dict) or geometry.get("kind") != "column" or all(
            _unset(geometry.get(k)) for k in ("mass", "mass_file")):
        return
    try:
        geo = Geometry.model_validate(geometry)
        gate = Gate.model_validate(data.get("gate", {}))
        setup = build_scene(geo, gate)
    except (ValueError, GeometryError):   # the validation that follows says what is wrong
        return
    ring = setup.mass
    sizes = {"width": float(ring[:, 0].max() - ring[:, 0].min()),
             "height": setup.mass_height()}
    for key, value in sizes.items():
        given = geometry.get(key)
        if given != base.get("geometry", {}).get(key) and given != value:
            raise ConfigError(f"geometry.{key} = {given!r} and the mass polygon both set the "
                              f"mass's {key} ({value:.4g} m); remove geometry.{key}")
        geometry[key] = value
        base.setdefault("geometry", {})[key] = value


def _unset(value: Any) -> bool:
    return value is None or (isinstance(value, str) and value.lower() == "none")
