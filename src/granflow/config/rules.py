"""Cross-field rules of the configuration: consistency, mesh size, and keys without effect.

Kept apart from the schema and the loading (``loading.py``): these rules read a
validated ``Config``. ``inert_keys`` is what a user who sets such a key is told about;
every other key changes a result (tests/unit/test_config_keys.py walks the schema).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import TYPE_CHECKING

from granflow.config.cost import bulk_area, cost_problems, estimated_triangles, front_run
from granflow.config.geometry_rules import geometry_inert_keys, geometry_problems
from granflow.config.messages import fmt_value
from granflow.config.schema import Layer, Material

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config

MAX_TRIANGLES = 100_000   # about 3.5 GB of peak memory (benchmarks/scaling.py: 2.9 GB at 80,000)
MAX_STEPS = 10**7         # fewest steps a run may need: at ~10 ms a step, more than a day
GB_PER_TRIANGLE = 33e-6   # peak memory growth per triangle (benchmarks/scaling.py)


def problems(c: Config) -> Iterator[str]:
    """Cross-field checks."""
    t, g, m = c.time, c.geometry, c.mesh
    key, step = ("time.dt", t.dt) if t.dt is not None else ("time.dt_max", t.dt_max)
    fewest_steps = t.t_end / step
    if fewest_steps > MAX_STEPS:
        yield (f"{key} = {step!r} needs at least "
               f"{fewest_steps:.2g} steps to time.t_end = {t.t_end!r} (at most {MAX_STEPS:.0e} "
               f"allowed: weeks of computing); use {key} >= {t.t_end / MAX_STEPS:.2g}")
    if t.dt_init > t.dt_max:
        yield f"time.dt_init = {t.dt_init!r} must not exceed time.dt_max = {t.dt_max!r}"
    for x in t.output_times:
        if not 0 < x <= t.t_end:
            yield (f"time.output_times = {fmt_value(t.output_times)}: {x!r} is not in "
                   f"(0, time.t_end = {t.t_end!r}]")
    if any(b <= a for a, b in zip(t.output_times, t.output_times[1:], strict=False)):
        yield f"time.output_times = {fmt_value(t.output_times)}: must be increasing"
    if g.kind == "periodic-layer":
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
    else:
        side = min(g.width, g.height)
        if m.size > side:
            yield (f"mesh.size = {m.size!r} must not exceed "
                   f"min(geometry.width, geometry.height) = {side!r}")
        if g.erodible_thickness > 0 and g.bed_length <= g.width:
            yield (f"geometry.bed_length = {g.bed_length!r} must be greater than "
                   f"geometry.width = {g.width!r} (the erodible layer must reach beyond the "
                   "column)")
        if g.erodible_thickness > 0 and 0 < m.layer_ahead < m.size:
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
        builtin = g.mass is None and g.mass_file is None     # (a user's mass: no shape)
        if (builtin and g.shape == "trapezoid"
                and front_run(g.height, g.front_angle_deg) >= g.width):
            yield (f"geometry.front_angle_deg = {g.front_angle_deg!r} is too shallow for this "
                   "column: its top width, width - height / tan(front_angle), must be > 0")
        else:                                   # (the scene is built only from a valid shape)
            yield from geometry_problems(c)
    st = c.surface_tension
    if st.release_angle_deg > st.trigger_angle_deg:
        yield (f"surface_tension.release_angle_deg = {st.release_angle_deg!r} must not exceed "
               f"surface_tension.trigger_angle_deg = {st.trigger_angle_deg!r}")
    bulk, layer = estimated_triangles(c)
    if layer > MAX_TRIANGLES / 2:
        yield (f"geometry.erodible_thickness = {g.erodible_thickness!r} with mesh.layer_cells "
               f"= {m.layer_cells} and geometry.bed_length = {g.bed_length!r} gives about "
               f"{layer:.2g} triangles in the layer (at most {MAX_TRIANGLES // 2} allowed); "
               "use a thicker or shorter layer, or fewer mesh.layer_cells")
    elif bulk + layer > MAX_TRIANGLES:
        if g.kind == "column":
            smallest = math.sqrt(bulk_area(c) / 0.433 / (MAX_TRIANGLES - layer))
        elif m.cells_x:     # 2 cells_x H / size triangles
            smallest = 2 * m.cells_x * g.height / MAX_TRIANGLES
        else:               # 2 L H / size^2
            smallest = math.sqrt(2 * g.length * g.height / MAX_TRIANGLES)
        yield (f"mesh.size = {m.size!r} gives about {bulk + layer:.2g} triangles, about "
               f"{0.3 + GB_PER_TRIANGLE * (bulk + layer):.2g} GB of memory (at most "
               f"{MAX_TRIANGLES} triangles allowed); use mesh.size >= {smallest:.2g}")
    yield from _layer_problems(c)
    yield from cost_problems(c)
    yield from _friction_problems(c)
    yield from _nonlocal_problems(c)
    mat = c.material
    if c.numerics.method == "augmented-lagrangian" and mat.rheology != "drucker-prager":
        yield (f"numerics.method = 'augmented-lagrangian' needs material.rheology = "
               f"'drucker-prager' (not {mat.rheology!r})")
    if mat.rheology == "mu-i":
        if mat.mu_2_deg <= mat.friction_angle_deg:
            yield (f"material.mu_2_deg = {mat.mu_2_deg!r} must be greater than "
                   f"material.friction_angle_deg = {mat.friction_angle_deg!r} (mu(I) rises "
                   "from mu_s to mu_2)")
        if mat.grain_density < mat.density:
            yield (f"material.grain_density = {mat.grain_density!r} must be at least "
                   f"material.density = {mat.density!r} (their ratio is the packing fraction)")


def _layer_problems(c: Config) -> Iterator[str]:
    """A layer of its own material ([layer]): one the regularised law can carry, and a
    consistent mu(I) if it has one."""
    own = {k: v for k, v in c.layer.model_dump().items() if v is not None}
    if not own or c.geometry.kind != "column" or c.geometry.erodible_thickness <= 0:
        return
    if c.numerics.method == "augmented-lagrangian" and c.material.model_copy(update=own) != (
            c.material):
        yield (f"numerics.method = 'augmented-lagrangian' needs one material, and [layer] sets "
               f"{', '.join(f'layer.{k}' for k in own)}; use numerics.method = 'regularized'")
    layer = c.material.model_copy(update=own)
    if layer.rheology == "mu-i" and layer.mu_2_deg <= layer.friction_angle_deg:
        yield (f"layer.mu_2_deg = {layer.mu_2_deg!r} must be greater than the layer's "
               f"friction angle {layer.friction_angle_deg!r} (mu(I) rises from mu_s to mu_2)")
    if layer.rheology == "mu-i" and layer.grain_density < layer.density:
        yield (f"layer.grain_density = {layer.grain_density!r} must be at least the layer's "
               f"density {layer.density!r} (their ratio is the packing fraction)")


HYSTERESIS_KEYS = ("start_friction_angle_deg", "mobilisation_time", "rest_time",
                   "mobilisation_shear_rate", "initial_mobilisation")
CREEP_MARGIN = 100.0   # mobilisation_shear_rate / eps at least: the creep of (2.13) at rest,
                       # eps ratio / sqrt(1 - ratio^2), passes it only within 5e-5 of yield


def _materials(c: Config) -> dict[str, Material]:
    """The run's materials by section: [material], and the layer's when the run has an
    erodible layer ([material] with what [layer] sets over it)."""
    out = {"material": c.material}
    if c.geometry.kind == "column" and c.geometry.erodible_thickness > 0:
        own = {k: v for k, v in c.layer.model_dump().items() if v is not None}
        out["layer"] = c.material.model_copy(update=own)
    return out


def _hysteretic_materials(c: Config) -> dict[str, Material]:
    """The run's materials with a hysteretic friction, by section ("material", "layer")."""
    return {k: m for k, m in _materials(c).items() if m.friction == "hysteretic"}


def _friction_problems(c: Config) -> Iterator[str]:
    """A hysteretic friction: the start friction at least the flow's, a threshold far above
    the regularisation's creep, and a method that takes a friction field."""
    materials = _hysteretic_materials(c)
    for section, mat in materials.items():
        if mat.start_friction_angle_deg < mat.friction_angle_deg:
            yield (f"{section}.start_friction_angle_deg = {mat.start_friction_angle_deg!r} must "
                   f"be at least the friction angle {mat.friction_angle_deg!r} (the "
                   "friction at rest is the larger)")
        if mat.mobilisation_shear_rate < CREEP_MARGIN * c.numerics.eps:
            yield (f"{section}.mobilisation_shear_rate = {mat.mobilisation_shear_rate!r} must be "
                   f"at least {CREEP_MARGIN:g} x numerics.eps = "
                   f"{CREEP_MARGIN * c.numerics.eps:.3g} (material at rest creeps at rates of "
                   "order eps and must not count as sheared)")
    if materials and c.numerics.method == "augmented-lagrangian":
        yield ("numerics.method = 'augmented-lagrangian' needs a constant friction; use "
               "'regularized' with friction = 'hysteretic'")


NONLOCAL_KEYS = ("nonlocal_amplitude", "nonlocal_b", "fluidity_time")


def _nonlocal_materials(c: Config) -> dict[str, Material]:
    """The run's materials that follow the nonlocal law, by section."""
    return {k: m for k, m in _materials(c).items() if m.rheology == "nonlocal"}


def _nonlocal_problems(c: Config) -> Iterator[str]:
    """The nonlocal law: a positive static friction (its rest state's fluidity is
    sqrt(2) eps / mu_s), grains denser than the bulk, no hysteretic friction beside it,
    and both materials nonlocal or neither (one fluidity field across the interface)."""
    materials = _materials(c)
    nonlocal_ = _nonlocal_materials(c)
    if not nonlocal_:
        return
    if len(nonlocal_) != len(materials):
        yield (f"layer.rheology = {materials['layer'].rheology!r} beside material.rheology = "
               f"{c.material.rheology!r}: a nonlocal material needs the other one nonlocal "
               "too (one fluidity field crosses the interface); set both or neither")
    for section, mat in nonlocal_.items():
        if mat.friction_angle_deg <= 0:
            yield (f"{section}.friction_angle_deg = {mat.friction_angle_deg!r} must be > 0 with "
                   "rheology = 'nonlocal' (mu_s > 0 sets the fluidity of material at rest)")
        if mat.friction == "hysteretic":
            yield (f"{section}.friction = 'hysteretic' cannot be combined with rheology = "
                   "'nonlocal': the fluidity already makes layers thinner than h_stop stop; "
                   "use friction = 'constant'")
        if mat.grain_density < mat.density:
            yield (f"{section}.grain_density = {mat.grain_density!r} must be at least the "
                   f"density {mat.density!r} (their ratio is the packing fraction)")


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
    """Keys that change nothing in a run of ``c``, each with the reason (shown to a user
    who sets one). Every other key changes a result (tests/unit/test_config_keys.py)."""
    g, t, st = c.geometry, c.time, c.surface_tension
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    layer_keys = " ".join(f"layer.{k}" for k in Layer.model_fields)
    erodible = g.kind == "column" and g.erodible_thickness > 0
    layer_law = (c.layer.rheology or c.material.rheology) if erodible else "drucker-prager"
    if c.material.rheology == "drucker-prager" and layer_law == "drucker-prager":
        add("material.mu_2_deg material.i0 material.grain_density"
            + ("" if erodible else " material.grain_diameter"),
            "it is a parameter of mu(I), and material.rheology = 'drucker-prager'"
            + (" (the layer's too)" if erodible else ""))
    elif c.material.rheology == "nonlocal" and layer_law == "nonlocal":
        add("material.mu_2_deg material.i0", "it is a parameter of mu(I), and "
            "material.rheology = 'nonlocal' (whose local law is mu_s + b I)")
    nonlocal_ = _nonlocal_materials(c)
    if "material" not in nonlocal_:
        add(" ".join(f"material.{k}" for k in NONLOCAL_KEYS), "it is a parameter of the "
            "nonlocal law, and material.rheology is not 'nonlocal'")
    if erodible and "layer" not in nonlocal_:
        add(" ".join(f"layer.{k}" for k in NONLOCAL_KEYS), "it is a parameter of the "
            "nonlocal law, and the layer's (layer.rheology, else material.rheology) is not "
            "'nonlocal'")
    if not nonlocal_:
        add("numerics.fluidity_coupling initial.fluidity boundary.bed_fluidity",
            "it is a setting of the nonlocal law's fluidity, and no material is 'nonlocal'")
    elif g.kind == "column":
        add("initial.fluidity", "a column starts at rest (g = 0); it sets a periodic layer's "
            "initial fluidity")
    if not erodible:
        add(layer_keys, "it describes the erodible layer's material, and there is none "
            "(geometry.erodible_thickness = 0 or geometry.kind = 'periodic-layer')")
    elif layer_law == "drucker-prager":
        add("layer.mu_2_deg layer.i0 layer.grain_density", "it is a parameter of mu(I), and "
            "the layer's law (layer.rheology, else material.rheology) is 'drucker-prager'")
    if g.kind == "periodic-layer":
        add("geometry.shape geometry.width geometry.front_angle_deg geometry.erodible_thickness "
            "geometry.bed_length geometry.axisymmetric",
            "it describes a column, and geometry.kind = 'periodic-layer'")
        add("boundary.channel_width boundary.side_wall_friction_deg",
            "the periodic layer is infinitely wide (the plane shear of section 4)")
        add("boundary.bed_friction_deg boundary.wall_friction_deg boundary.penalty "
            "boundary.normal_load numerics.eps_friction boundary.bed_fluidity",
            "the periodic layer has a no-slip bed and no walls")
        add("mesh.remesh_quality mesh.failure_remesh_quality mesh.layer_cells mesh.layer_ahead "
            "mesh.layer_aspect mesh.adaptive mesh.rest_coarsening mesh.layer_rest_coarsening "
            "mesh.flow_margin "
            "numerics.volume_correction time.stop_at_rest time.rest_fraction "
            "time.rest_duration surface_tension.enabled surface_tension.delta "
            "surface_tension.gamma0 surface_tension.trigger_angle_deg "
            "surface_tension.release_angle_deg surface_tension.length mesh.cells_across",
            "it applies to columns only")
        if c.numerics.mesh_velocity == "fixed":
            add("numerics.mesh_penalty numerics.ale_extrapolation",
                "numerics.mesh_velocity = 'fixed' (the mesh does not move)")
    else:
        add("geometry.length initial.shear_rate initial.plug_base mesh.cells_x",
            "it describes the periodic layer, and geometry.kind = 'column'")
        if g.axisymmetric:
            add("boundary.wall_friction_deg", "geometry.axisymmetric = true: x = 0 is the "
                "symmetry axis (u_r = 0, no friction), not a wall")
        if g.erodible_thickness == 0:
            add("geometry.bed_length mesh.layer_cells mesh.layer_ahead mesh.layer_aspect "
                "mesh.layer_rest_coarsening",
                "it describes the erodible layer, and geometry.erodible_thickness = 0")
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
    if t.dt is not None:
        add("time.dt_init time.dt_max time.dt_growth time.error_tol time.error_floor "
            "numerics.tol_init", "time.dt sets a fixed step")
        if t.adaptive:   # (adaptive = false with a fixed dt says the same thing twice: fine)
            add("time.adaptive", "time.dt sets a fixed step; unset it for adaptive steps")
    elif t.adaptive:
        add("time.dt_growth numerics.tol_init", "time.adaptive = true (no ramp)")
    else:
        add("time.error_tol time.error_floor", "time.adaptive = false")
    hysteretic = _hysteretic_materials(c)
    if not hysteretic:
        add(" ".join(f"material.{k}" for k in HYSTERESIS_KEYS),
            "it is a parameter of the hysteretic friction, and material.friction = 'constant'"
            + (" (the layer's too)" if erodible else ""))
    if erodible and "layer" not in hysteretic:
        add(" ".join(f"layer.{k}" for k in HYSTERESIS_KEYS), "it is a parameter of the "
            "hysteretic friction, and the layer's (layer.friction, else material.friction) "
            "is 'constant'")
    if c.numerics.method == "regularized":
        add("numerics.al_r", "numerics.method = 'regularized'")
    else:
        add("numerics.eps numerics.linearization",
            "numerics.method = 'augmented-lagrangian' (no regularisation, its own iteration)")
    if (c.numerics.linearization in ("newton", "hybrid") and c.numerics.method == "regularized"
            and c.numerics.initial_guess != "auto"):
        add("numerics.initial_guess", "Newton and the hybrid start from the extrapolated "
            "state unless it is 'auto'")
    if c.numerics.linearization == "newton" or c.numerics.method != "regularized":
        add("numerics.anderson_depth", "it accelerates the fixed-point iteration (3.2), "
            "which numerics.linearization = 'newton' and the augmented Lagrangian do not run")
    out.update(geometry_inert_keys(c))
    return out
