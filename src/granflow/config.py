"""Configuration: frozen, validated parameter models and their layered loading.

Layers, each overriding the one before (pyro2-style):

1. package defaults, ``granflow/defaults.toml`` (the one place where defaults live);
2. a scenario: a built-in name, or a TOML file, which may start from a built-in one with a
   top-level ``scenario = "NAME"``;
3. ``--set section.key=value`` overrides, the value read as a TOML literal
   (``1e-4``, ``true``, ``[0.1, 0.2]``, ``"newton"``) or else as a bare string.

TOML has no null, so an optional value is unset with the string ``"none"``. Unknown keys,
out-of-range values and inconsistent combinations raise :class:`ConfigError`, whose message
is one line naming the key, the value and what is allowed. Units are SI, angles in degrees.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Iterator, Sequence
from importlib import resources
from pathlib import Path
from types import NoneType, UnionType
from typing import Annotated, Any, Literal, Union, get_args, get_origin

import annotated_types as at
import tomli_w
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator
from pydantic.fields import FieldInfo
from pydantic_core import PydanticCustomError

from granflow.scenarios.registry import builtin_scenarios, scenario_text

__all__ = ["CUSTOM", "Config", "ConfigError", "apply_overrides", "builtin_scenarios",
           "config_to_toml", "load_config", "parse_value"]

CUSTOM = "custom"  # scenario name of a TOML file that starts from the package defaults only
TOML_HEADER = "# granflow resolved configuration: rerun with `granflow run config.toml`\n"


class ConfigError(ValueError):
    """Invalid configuration; the message is one line naming the key, value and allowed range."""


Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Angle = Annotated[float, Field(ge=0, lt=90)]
Fraction = Annotated[float, Field(gt=0, lt=1)]


class _Section(BaseModel):
    """Base of every model: frozen, strict types (no str -> float coercion), no extra keys."""

    model_config = ConfigDict(frozen=True, extra="forbid", strict=True, allow_inf_nan=False)

    @model_validator(mode="before")
    @classmethod
    def _unset_none(cls, data: Any) -> Any:
        # TOML has no null: the string "none" unsets an optional field.
        if not isinstance(data, dict):
            return data
        return {
            k: None if _is_none(v) and k in cls.model_fields and _optional(cls, k) else v
            for k, v in data.items()
        }


def _is_none(value: Any) -> bool:
    return isinstance(value, str) and value.lower() == "none"


def _optional(model: type[BaseModel], key: str) -> bool:
    return NoneType in get_args(model.model_fields[key].annotation)


class Material(_Section):
    density: Positive  # rho (kg/m^3)
    viscosity: Positive  # dynamic viscosity eta (Pa s)
    friction_angle_deg: Annotated[float, Field(gt=0, lt=90)]  # delta, mu_s = tan(delta)
    rheology: Literal["drucker-prager", "mu-i"]
    gravity: Positive  # g (m/s^2)

    @property
    def mu_s(self) -> float:
        """Internal friction coefficient tan(delta); kappa = sqrt(2) mu_s [p]_+ (2.13)."""
        return math.tan(math.radians(self.friction_angle_deg))

    @property
    def kinematic_viscosity(self) -> float:
        """nu = eta / rho (m^2/s)."""
        return self.viscosity / self.density


class Geometry(_Section):
    kind: Literal["periodic-layer", "column"]
    slope_deg: Angle  # bed inclination theta
    length: Positive  # periodic layer: length l
    height: Positive  # layer height h, or column height h0
    shape: Literal["trapezoid", "rectangle"]  # column
    width: Positive  # column base width l0
    front_angle_deg: Annotated[float, Field(gt=0, le=90)]  # column front angle alpha0
    erodible_thickness: NonNegative  # column: he, 0 = rigid bed
    bed_length: Positive  # column: bed length from the left wall


class Boundary(_Section):
    bed_friction_deg: Angle  # Coulomb mu_b = tan(angle)
    wall_friction_deg: Angle  # Coulomb mu_l = tan(angle)
    penalty: Positive  # enforces u.n = 0 on the bed and the wall
    normal_load: Literal["pressure", "reaction"]  # friction load: [p - sigma'_N]_+ or [xi u.N]_+

    @property
    def mu_bed(self) -> float:
        return math.tan(math.radians(self.bed_friction_deg))

    @property
    def mu_wall(self) -> float:
        return math.tan(math.radians(self.wall_friction_deg))


class Initial(_Section):
    shear_rate: NonNegative  # plug flow: U0 = shear_rate [Z - plug_base]_+
    plug_base: NonNegative


class Mesh(_Section):
    size: Positive  # target edge length (m)
    cells_x: Annotated[int, Field(ge=2)] | None  # periodic layer; None = round(length / size)
    remesh_quality: Annotated[float, Field(ge=0, lt=1)]  # column: also remesh below; 0 = off
    failure_remesh_quality: Annotated[float, Field(ge=0, lt=1)]  # remesh a failed solve below
    layer_cells: Annotated[int, Field(ge=1, le=16)]  # cells across an erodible layer


class Numerics(_Section):
    eps: Positive  # regularisation epsilon of (2.13)
    eps_friction: Positive  # regularisation of the Coulomb friction
    tol: Fraction  # stopping tolerance of the fixed-point iteration (3.2)
    tol_init: Fraction | None  # start tolerance of the ramp; None = tol
    max_iterations: Annotated[int, Field(ge=1)]
    linearization: Literal["picard", "newton", "hybrid"]
    mesh_velocity: Literal["fixed", "vertical", "elastic", "lagrange"]
    mesh_penalty: Positive
    velocity_floor: Annotated[float, Field(ge=0)]  # m/s, floor of ||u|| in the (3.2) criterion
    volume_correction: bool  # restore the initial area after each ALE move (column only)
    ale_extrapolation: bool  # mesh velocity of the extrapolated mid-step velocity (2nd order)
    linear_solver: Literal["auto", "umfpack", "pardiso"]  # auto: PARDISO when MKL is there
    initial_guess: Literal["previous", "extrapolated"]  # first iterate of (3.2)

    @property
    def tol_start(self) -> float:
        return self.tol if self.tol_init is None else self.tol_init


class Time(_Section):
    t_end: Positive
    dt: Positive | None  # fixed step; overrides the ramp
    dt_init: Positive
    dt_max: Positive
    dt_growth: Annotated[float, Field(ge=1)]
    adaptive: bool  # error-controlled steps; false keeps the paper's ramp (3.1)
    error_tol: Fraction  # adaptive: local velocity error per step / RMS speed
    error_floor: Positive  # adaptive: m/s, RMS speed below which the error is absolute
    stop_at_rest: bool  # end the run once the mass has come to rest
    rest_fraction: Annotated[float, Field(ge=0, lt=1)]  # flowing area at rest, at most
    rest_duration: NonNegative  # s the mass must stay at rest before the run ends
    output_times: list[float]


class SurfaceTension(_Section):
    enabled: bool
    delta: Positive  # extent of the tension around the tip, in surface nodes (3.11)
    gamma0: Literal["auto"] | NonNegative  # gamma0-bar of (3.11)
    trigger_angle_deg: Annotated[float, Field(ge=0, le=180)]  # on where the surface turns >=
    release_angle_deg: Annotated[float, Field(ge=0, le=180)]  # stays on while it turns >=


class Output(_Section):
    vtk_every: Annotated[int, Field(ge=0)]  # 0 = only at output_times
    checkpoint_every: Annotated[int, Field(ge=0)]  # 0 = only when interrupted or failed
    progress: bool


class Config(_Section):
    """The fully resolved configuration of one run."""

    scenario: str
    material: Material
    geometry: Geometry
    boundary: Boundary
    initial: Initial
    mesh: Mesh
    numerics: Numerics
    time: Time
    surface_tension: SurfaceTension
    output: Output

    @model_validator(mode="after")
    def _consistent(self) -> Config:
        for problem in _problems(self):
            raise PydanticCustomError("granflow_config", "{message}", {"message": problem})
        return self


SECTIONS: dict[str, type[_Section]] = {
    name: field.annotation
    for name, field in Config.model_fields.items()
    if isinstance(field.annotation, type) and issubclass(field.annotation, _Section)
}


def _problems(c: Config) -> Iterator[str]:
    """Cross-field checks, then choices whose names are reserved but not implemented yet."""
    t, g, m = c.time, c.geometry, c.mesh
    if t.dt_init > t.dt_max:
        yield f"time.dt_init = {t.dt_init!r} must not exceed time.dt_max = {t.dt_max!r}"
    for x in t.output_times:
        if not 0 < x <= t.t_end:
            yield (f"time.output_times = {_fmt(t.output_times)}: {x!r} is not in "
                   f"(0, time.t_end = {t.t_end!r}]")
    if any(b <= a for a, b in zip(t.output_times, t.output_times[1:], strict=False)):
        yield f"time.output_times = {_fmt(t.output_times)}: must be increasing"
    if g.kind == "periodic-layer":
        side = min(g.length, g.height)
        if m.size > side:
            yield (f"mesh.size = {m.size!r} must not exceed "
                   f"min(geometry.length, geometry.height) = {side!r}")
        if c.initial.plug_base >= g.height:
            yield (f"geometry.height = {g.height!r} must be greater than "
                   f"initial.plug_base = {c.initial.plug_base!r}")
        if c.material.friction_angle_deg < g.slope_deg:
            yield (f"material.friction_angle_deg = {c.material.friction_angle_deg!r} must be >= "
                   f"geometry.slope_deg = {g.slope_deg!r}, or the layer can never stop")
        if c.numerics.mesh_velocity in ("elastic", "lagrange"):
            yield (f"numerics.mesh_velocity = {c.numerics.mesh_velocity!r} is not available for "
                   "geometry.kind = 'periodic-layer'; use 'fixed' or 'vertical'")
    else:
        side = min(g.width, g.height)
        if m.size > side:
            yield (f"mesh.size = {m.size!r} must not exceed "
                   f"min(geometry.width, geometry.height) = {side!r}")
        if g.bed_length <= g.width:
            yield (f"geometry.bed_length = {g.bed_length!r} must be greater than "
                   f"geometry.width = {g.width!r}")
        if g.erodible_thickness >= g.height:
            yield (f"geometry.erodible_thickness = {g.erodible_thickness!r} must be less than "
                   f"geometry.height = {g.height!r}")
        if c.numerics.mesh_velocity in ("fixed", "vertical"):
            yield (f"numerics.mesh_velocity = {c.numerics.mesh_velocity!r} is not available for "
                   "geometry.kind = 'column' (its free surface must move); "
                   "use 'elastic' (3.6) or 'lagrange' (3.7)")
        run = g.height / math.tan(math.radians(g.front_angle_deg))  # horizontal extent of front
        if g.shape == "trapezoid" and run >= g.width:
            yield (f"geometry.front_angle_deg = {g.front_angle_deg!r} is too shallow for this "
                   "column: its top width, width - height / tan(front_angle), must be > 0")
    st = c.surface_tension
    if st.release_angle_deg > st.trigger_angle_deg:
        yield (f"surface_tension.release_angle_deg = {st.release_angle_deg!r} must not exceed "
               f"surface_tension.trigger_angle_deg = {st.trigger_angle_deg!r}")
    not_yet = {
        "material.rheology": (c.material.rheology, "mu-i", "'drucker-prager'"),
    }
    for key, (value, reserved, use) in not_yet.items():
        if value == reserved:
            yield f"{key} = {_fmt(value)} is not implemented yet; use {use}"


# ---------------------------------------------------------------- loading and layering


def load_config(source: str | Path, overrides: Sequence[str] = ()) -> Config:
    """Resolve defaults -> scenario (built-in name or TOML file) -> ``--set`` overrides."""
    data = _defaults()
    name, layers = _read_source(source)
    for layer in layers:
        _merge(data, layer)
    explicit = "output_times" in layers[-1].get("time", {}) if len(layers) > 1 else False
    _apply(data, overrides)
    explicit = explicit or any(o.partition("=")[0].strip() == "time.output_times"
                               for o in overrides)
    if not explicit:  # inherited output times after a shortened t_end are dropped
        t_end = data["time"]["t_end"]
        data["time"]["output_times"] = [x for x in data["time"]["output_times"] if x <= t_end]
    data["scenario"] = name
    return _validate(data)


def apply_overrides(config: Config, overrides: Sequence[str]) -> Config:
    """A copy of ``config`` with ``section.key=value`` overrides applied and re-validated."""
    data = config.model_dump()
    _apply(data, overrides)
    return _validate(data)


def config_to_toml(config: Config) -> str:
    """The resolved configuration as TOML, loadable as is by :func:`load_config`."""
    data = config.model_dump()
    for section in SECTIONS:
        data[section] = {k: "none" if v is None else v for k, v in data[section].items()}
    return TOML_HEADER + tomli_w.dumps(data)


def _defaults() -> dict[str, Any]:
    text = resources.files("granflow").joinpath("defaults.toml").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    _check_keys(data)
    return {section: dict(data.get(section, {})) for section in SECTIONS}


def _read_source(source: str | Path) -> tuple[str, list[dict[str, Any]]]:
    """The scenario name and the TOML layers (base scenario first) that ``source`` stands for."""
    text = str(source)
    if isinstance(source, Path) or text.endswith(".toml") or "/" in text:
        path = Path(source)
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except FileNotFoundError:
            raise ConfigError(f"scenario file '{path}' not found") from None
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as err:
            raise ConfigError(f"cannot read scenario file '{path}': {err}") from None
        _check_keys(data)
        base = data.pop("scenario", CUSTOM)
        if base == CUSTOM:
            return CUSTOM, [data]
        return base, [_builtin(base, where=f" (named by 'scenario' in {path})"), data]
    return text, [_builtin(text)]


def _builtin(name: Any, where: str = "") -> dict[str, Any]:
    names = builtin_scenarios()
    if name not in names:
        raise ConfigError(f"unknown scenario {_fmt(name)}{where}; built-in scenarios: "
                          f"{', '.join(names)}; or give the path of a .toml file")
    data = tomllib.loads(scenario_text(name))
    data.pop("scenario", None)
    _check_keys(data)
    return data


def _check_keys(data: dict[str, Any]) -> None:
    """Reject unknown sections and keys, naming the known ones."""
    for section, table in data.items():
        if section == "scenario":
            continue
        if section not in SECTIONS:
            raise ConfigError(f"unknown configuration section '{section}' "
                              f"(known sections: {', '.join(SECTIONS)}; top-level key: scenario)")
        if not isinstance(table, dict):
            raise ConfigError(f"'{section}' must be a table [{section}] of keys, not {_fmt(table)}")
        known = SECTIONS[section].model_fields
        for key in table:
            if key not in known:
                raise ConfigError(f"unknown configuration key '{section}.{key}' "
                                  f"(known keys in [{section}]: {', '.join(known)})")


def _merge(data: dict[str, Any], layer: dict[str, Any]) -> None:
    for section, table in layer.items():
        data.setdefault(section, {}).update(table)


def _apply(data: dict[str, Any], overrides: Sequence[str]) -> None:
    for text in overrides:
        key, sep, raw = text.partition("=")
        key = key.strip()
        if not sep or not key:
            raise ConfigError(f"--set expects section.key=value, got {text!r}")
        section, dot, name = key.partition(".")
        if not dot:
            raise ConfigError(f"unknown configuration key '{key}' (keys are section.key, "
                              f"sections: {', '.join(SECTIONS)})")
        _check_keys({section: {name: None}})
        data[section][name] = parse_value(raw)


def parse_value(raw: str) -> Any:
    """A ``--set`` value: a TOML literal if it is one, else a Python float (``.5``, ``1.``),
    else the bare string (so ``--set numerics.linearization=newton`` needs no quotes)."""
    raw = raw.strip()
    try:
        parsed = tomllib.loads(f"v = {raw}")
    except tomllib.TOMLDecodeError:
        try:
            return float(raw)
        except ValueError:
            return raw
    return parsed["v"] if list(parsed) == ["v"] else raw


# ---------------------------------------------------------------- error messages


def _validate(data: dict[str, Any]) -> Config:
    try:
        return Config.model_validate(data)
    except ValidationError as err:
        raise ConfigError(_one_line(err.errors()[0], data)) from None


def _one_line(error: Any, data: dict[str, Any]) -> str:
    """``section.key = value: must be ...`` from the first pydantic error."""
    loc = error["loc"]
    if error["type"] == "granflow_config":
        return error["ctx"]["message"]
    if len(loc) < 2 or loc[0] not in SECTIONS:
        return f"{'.'.join(map(str, loc)) or 'configuration'}: {error['msg']}"
    section, key = loc[0], loc[1]
    model = SECTIONS[section]
    if key not in model.model_fields:
        return f"unknown configuration key '{section}.{key}'"
    field = model.model_fields[key]
    allowed = _describe(field.annotation, field.metadata)
    if error["type"] == "missing":
        return f"{section}.{key} is not set: it must be {allowed}"
    value = data.get(section, {}).get(key, error.get("input"))
    return f"{section}.{key} = {_fmt(value)}: must be {allowed}"


def _describe(tp: Any, metadata: Sequence[Any] = ()) -> str:
    """Plain words for the values a field accepts, read from its type and bounds."""
    origin, args = get_origin(tp), get_args(tp)
    if origin in (Union, UnionType):
        text = " or ".join(_describe(a) for a in args if a is not NoneType)
        return text + (" or none" if NoneType in args else "")
    if origin is Annotated:
        return _describe(args[0], [*metadata, *tp.__metadata__])
    if origin is Literal:
        names = [repr(a) for a in args]
        return names[0] if len(names) == 1 else "one of " + ", ".join(names)
    if tp is bool:
        return "true or false"
    if origin is list:
        return "a list of numbers"
    if tp is str:
        return "a string"
    bounds: dict[str, float] = {}
    for item in metadata:
        for m in item.metadata if isinstance(item, FieldInfo) else [item]:
            for cls, sym in ((at.Gt, "gt"), (at.Ge, "ge"), (at.Lt, "lt"), (at.Le, "le")):
                if isinstance(m, cls):
                    bounds[sym] = getattr(m, sym)
    noun = "an integer" if tp is int else "a number"
    lo = ("(", bounds["gt"]) if "gt" in bounds else ("[", bounds["ge"]) if "ge" in bounds else None
    hi = (")", bounds["lt"]) if "lt" in bounds else ("]", bounds["le"]) if "le" in bounds else None
    if lo and hi:
        return f"{noun} in {lo[0]}{lo[1]:g}, {hi[1]:g}{hi[0]}"
    if lo:
        return f"{noun} {'>' if lo[0] == '(' else '>='} {lo[1]:g}"
    if hi:
        return f"{noun} {'<' if hi[0] == ')' else '<='} {hi[1]:g}"
    return noun


def _fmt(value: Any) -> str:
    """A value as the user would write it (TOML-like: true, 'text', [1.0, 2.0], none)."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    return repr(value)
