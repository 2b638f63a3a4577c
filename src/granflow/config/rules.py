"""Cross-field rules of the configuration: consistency, mesh size, and keys without effect.

Kept apart from the schema and the loading (``loading.py``): these rules read a
validated ``Config``. ``inert_keys`` is what a user who sets such a key is told about;
every other key changes a result (tests/unit/test_config_keys.py walks the schema).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from granflow.config.cost import cost_problems
from granflow.config.kinds import erodible_layer, rules_of
from granflow.config.messages import fmt_value
from granflow.config.schema import SECTIONS, MaterialKeys
from granflow.physics.laws import all_laws, described, keys_read, laws_of, selecting_key
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
        yield from law_checks(mat, section, c.numerics.eps)
    yield from _one_field_problems(c)
    mat = c.material
    if c.numerics.method == "augmented-lagrangian" and mat.rheology != "drucker-prager":
        yield (f"numerics.method = 'augmented-lagrangian' needs material.rheology = "
               f"'drucker-prager' (not {mat.rheology!r})")
    if c.numerics.method == "augmented-lagrangian" and any(
            m.packing != "none" for m in _materials(c).values()):
        yield ("numerics.method = 'augmented-lagrangian' needs an incompressible material "
               "(packing = 'none'); use 'regularized' with packing = 'critical-state'")
    if c.numerics.method == "augmented-lagrangian" and any(
            m.friction != "constant" for m in _materials(c).values()):
        yield ("numerics.method = 'augmented-lagrangian' needs a constant friction; use "
               "'regularized' with friction = " + repr(next(
                   m.friction for m in _materials(c).values() if m.friction != "constant")))


def _layer_problems(c: Config) -> Iterator[str]:
    """A layer of its own material ([layer]): one the regularised law can carry."""
    own = {k: v for k, v in c.layer.model_dump().items() if v is not None}
    if not own or not erodible_layer(c):
        return
    if c.numerics.method == "augmented-lagrangian" and c.material.model_copy(update=own) != (
            c.material):
        yield (f"numerics.method = 'augmented-lagrangian' needs one material, and [layer] sets "
               f"{', '.join(f'layer.{k}' for k in own)}; use numerics.method = 'regularized'")


def _materials(c: Config) -> dict[str, MaterialKeys]:
    """The run's materials by section: [material], and the layer's when the run has an
    erodible layer ([material] with what [layer] sets over it)."""
    out = {"material": c.material}
    if erodible_layer(c):
        own = {k: v for k, v in c.layer.model_dump().items() if v is not None}
        out["layer"] = c.material.model_copy(update=own)
    return out


def _one_field_problems(c: Config) -> Iterator[str]:
    """A law whose field crosses the interface (``Law.one_field``: the nonlocal fluidity)
    needs both materials to follow it, or neither."""
    materials = _materials(c)
    if len(materials) < 2:
        return
    for law in all_laws():
        users = [s for s, m in materials.items() if law in laws_of(m)]
        if law.one_field and len(users) == 1:
            key = selecting_key(law)
            yield (f"layer.{key} = {getattr(materials['layer'], key)!r} beside material.{key} "
                   f"= {getattr(c.material, key)!r}: a material that follows {law.described} "
                   "needs the other one to follow it too (one field crosses the interface); "
                   "set both or neither")


def _law_inert_keys(c: Config, add: Callable[[str, str], None]) -> None:
    """The keys of the laws a run's materials do not follow (a key of [material] is also
    the layer's unless [layer] sets it), the other sections' settings only such laws use,
    and the grains' keys where no law reads them (grain_diameter is also, over an erodible
    layer, the distance that counts as displaced)."""
    materials = _materials(c)
    named = ", ".join(f"{s}.{described(m)}" for s, m in materials.items())
    read = {k for m in materials.values() for k in keys_read(m)}
    used = {law.name for m in materials.values() for law in laws_of(m)}
    layer = materials.get("layer")
    for law in all_laws():
        why = (f"it is a parameter of {law.described} ({selecting_key(law)} = "
               f"{law.name!r}), and {named}")
        if law.name not in used:
            add(" ".join(f"material.{k}" for k in law.keys if k not in read), why)
            add(" ".join(law.settings), why)
        if layer is not None and law not in laws_of(layer):
            add(" ".join(f"layer.{k}" for k in law.keys if k not in keys_read(layer)), why)
    grains = {"grain_density"} | ({"grain_diameter"} if layer is None else set())
    add(" ".join(f"material.{k}" for k in sorted(grains - read)),
        f"no law of the run reads it ({named})")
    if layer is not None and "grain_density" not in keys_read(layer):
        add("layer.grain_density", f"no law of the layer reads it ({named})")


def inert_keys(c: Config) -> dict[str, str]:
    """Keys that change nothing in a run of ``c``, each with the reason (shown to a user
    who sets one). Every other key changes a result (tests/unit/test_config_keys.py)."""
    t = c.time
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    layer_keys = " ".join(f"layer.{k}" for k in SECTIONS["layer"].model_fields)
    _law_inert_keys(c, add)
    if not erodible_layer(c):
        add(layer_keys, "it describes the erodible layer's material, and there is none "
            "(geometry.erodible_thickness = 0 or geometry.kind = 'periodic-layer')")
    if t.dt is not None:
        add("time.dt_init time.dt_max time.dt_growth time.error_tol time.error_floor "
            "time.dt_max_slow time.slow_courant numerics.tol_init", "time.dt sets a fixed step")
        if t.adaptive:   # (adaptive = false with a fixed dt says the same thing twice: fine)
            add("time.adaptive", "time.dt sets a fixed step; unset it for adaptive steps")
    elif t.adaptive:
        add("time.dt_growth numerics.tol_init", "time.adaptive = true (no ramp)")
        if t.dt_max_slow is None or t.dt_max_slow <= t.dt_max:
            add("time.slow_courant", "time.dt_max_slow is unset or at most time.dt_max: "
                "the step's cap stays time.dt_max")
    else:
        add("time.error_tol time.error_floor time.dt_max_slow time.slow_courant",
            "time.adaptive = false")
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
