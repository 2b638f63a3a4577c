"""Cross-field rules of the configuration: consistency, mesh size, and keys without effect.

Kept apart from the schema and the loading (``loading.py``): these rules read a
validated ``Config``. ``inert_keys`` is what a user who sets such a key is told about;
every other key changes a result (tests/unit/test_config_keys.py walks the schema).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from granflow.config.cost import cost_problems
from granflow.config.kinds import erodible_layer, rules_of
from granflow.config.messages import fmt_value
from granflow.config.schema import Layer, Material
from granflow.physics.laws import FRICTIONS, RHEOLOGIES
from granflow.physics.laws import checks as law_checks

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
    kind = rules_of(c)
    yield from kind.problems(c)
    st = c.surface_tension
    if st.release_angle_deg > st.trigger_angle_deg:
        yield (f"surface_tension.release_angle_deg = {st.release_angle_deg!r} must not exceed "
               f"surface_tension.trigger_angle_deg = {st.trigger_angle_deg!r}")
    bulk, layer = kind.triangles(c)
    if layer > MAX_TRIANGLES / 2:
        yield (f"geometry.erodible_thickness = {g.erodible_thickness!r} with mesh.layer_cells "
               f"= {m.layer_cells} and geometry.bed_length = {g.bed_length!r} gives about "
               f"{layer:.2g} triangles in the layer (at most {MAX_TRIANGLES // 2} allowed); "
               "use a thicker or shorter layer, or fewer mesh.layer_cells")
    elif bulk + layer > MAX_TRIANGLES:
        smallest = kind.smallest_size(c, MAX_TRIANGLES - layer)
        yield (f"mesh.size = {m.size!r} gives about {bulk + layer:.2g} triangles, about "
               f"{0.3 + GB_PER_TRIANGLE * (bulk + layer):.2g} GB of memory (at most "
               f"{MAX_TRIANGLES} triangles allowed); use mesh.size >= {smallest:.2g}")
    yield from _layer_problems(c)
    yield from cost_problems(c)
    for section, mat in _materials(c).items():
        yield from law_checks(mat, section)
    yield from _friction_problems(c)
    yield from _nonlocal_problems(c)
    mat = c.material
    if c.numerics.method == "augmented-lagrangian" and mat.rheology != "drucker-prager":
        yield (f"numerics.method = 'augmented-lagrangian' needs material.rheology = "
               f"'drucker-prager' (not {mat.rheology!r})")


def _layer_problems(c: Config) -> Iterator[str]:
    """A layer of its own material ([layer]): one the regularised law can carry."""
    own = {k: v for k, v in c.layer.model_dump().items() if v is not None}
    if not own or not erodible_layer(c):
        return
    if c.numerics.method == "augmented-lagrangian" and c.material.model_copy(update=own) != (
            c.material):
        yield (f"numerics.method = 'augmented-lagrangian' needs one material, and [layer] sets "
               f"{', '.join(f'layer.{k}' for k in own)}; use numerics.method = 'regularized'")


HYSTERESIS_KEYS = FRICTIONS["hysteretic"].keys
CREEP_MARGIN = 100.0   # mobilisation_shear_rate / eps at least: the creep of (2.13) at rest,
                       # eps ratio / sqrt(1 - ratio^2), passes it only within 5e-5 of yield


def _materials(c: Config) -> dict[str, Material]:
    """The run's materials by section: [material], and the layer's when the run has an
    erodible layer ([material] with what [layer] sets over it)."""
    out = {"material": c.material}
    if erodible_layer(c):
        own = {k: v for k, v in c.layer.model_dump().items() if v is not None}
        out["layer"] = c.material.model_copy(update=own)
    return out


def _hysteretic_materials(c: Config) -> dict[str, Material]:
    """The run's materials with a hysteretic friction, by section ("material", "layer")."""
    return {k: m for k, m in _materials(c).items() if m.friction == "hysteretic"}


def _friction_problems(c: Config) -> Iterator[str]:
    """A hysteretic friction: a threshold far above the regularisation's creep, and a method
    that takes a friction field."""
    materials = _hysteretic_materials(c)
    for section, mat in materials.items():
        if mat.mobilisation_shear_rate < CREEP_MARGIN * c.numerics.eps:
            yield (f"{section}.mobilisation_shear_rate = {mat.mobilisation_shear_rate!r} must be "
                   f"at least {CREEP_MARGIN:g} x numerics.eps = "
                   f"{CREEP_MARGIN * c.numerics.eps:.3g} (material at rest creeps at rates of "
                   "order eps and must not count as sheared)")
    if materials and c.numerics.method == "augmented-lagrangian":
        yield ("numerics.method = 'augmented-lagrangian' needs a constant friction; use "
               "'regularized' with friction = 'hysteretic'")


NONLOCAL_KEYS = RHEOLOGIES["nonlocal"].keys


def _nonlocal_materials(c: Config) -> dict[str, Material]:
    """The run's materials that follow the nonlocal law, by section."""
    return {k: m for k, m in _materials(c).items() if m.rheology == "nonlocal"}


def _nonlocal_problems(c: Config) -> Iterator[str]:
    """The nonlocal law: both materials nonlocal or neither (one fluidity field across the
    interface)."""
    materials = _materials(c)
    nonlocal_ = _nonlocal_materials(c)
    if not nonlocal_:
        return
    if len(nonlocal_) != len(materials):
        yield (f"layer.rheology = {materials['layer'].rheology!r} beside material.rheology = "
               f"{c.material.rheology!r}: a nonlocal material needs the other one nonlocal "
               "too (one fluidity field crosses the interface); set both or neither")


def inert_keys(c: Config) -> dict[str, str]:
    """Keys that change nothing in a run of ``c``, each with the reason (shown to a user
    who sets one). Every other key changes a result (tests/unit/test_config_keys.py)."""
    t = c.time
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    layer_keys = " ".join(f"layer.{k}" for k in Layer.model_fields)
    erodible = erodible_layer(c)
    layer_law = (c.layer.rheology or c.material.rheology) if erodible else "drucker-prager"
    if c.material.rheology == "drucker-prager" and layer_law == "drucker-prager":
        add("material.mu_2_deg material.i0 material.grain_density"
            + ("" if erodible else " material.grain_diameter"),
            "it is a parameter of mu(I), and material.rheology = 'drucker-prager'"
            + (" (the layer's too)" if erodible else ""))
    elif c.material.rheology == "nonlocal" and layer_law == "nonlocal":
        # (mu_2_deg is read: the nonlocal law holds material at rest up to mu_2)
        add("material.i0", "it is a parameter of mu(I), and "
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
    if not erodible:
        add(layer_keys, "it describes the erodible layer's material, and there is none "
            "(geometry.erodible_thickness = 0 or geometry.kind = 'periodic-layer')")
    elif layer_law == "drucker-prager":
        add("layer.mu_2_deg layer.i0 layer.grain_density", "it is a parameter of mu(I), and "
            "the layer's law (layer.rheology, else material.rheology) is 'drucker-prager'")
    if t.dt is not None:
        add("time.dt_init time.dt_max time.dt_growth time.error_tol time.error_floor "
            "time.dt_max_slow time.slow_courant numerics.tol_init", "time.dt sets a fixed step")
        if t.adaptive:   # (adaptive = false with a fixed dt says the same thing twice: fine)
            add("time.adaptive", "time.dt sets a fixed step; unset it for adaptive steps")
    elif t.adaptive:
        add("time.dt_growth numerics.tol_init", "time.adaptive = true (no ramp)")
    else:
        add("time.error_tol time.error_floor time.dt_max_slow time.slow_courant",
            "time.adaptive = false")
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
    out.update(rules_of(c).inert_keys(c))
    return out
