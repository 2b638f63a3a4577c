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

import copy
import math
import tomllib
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from types import NoneType
from typing import Annotated, Any, Literal, get_args, get_origin

import tomli_w
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator
from pydantic_core import PydanticCustomError

from granflow.config_messages import one_line
from granflow.config_rules import _fmt, _problems, inert_keys
from granflow.scenarios.registry import builtin_scenarios, scenario_text

__all__ = ["CUSTOM", "Config", "ConfigError", "apply_overrides", "builtin_scenarios",
           "config_to_toml", "load_config", "parse_value"]

CUSTOM = "custom"  # scenario name of a TOML file that starts from the package defaults only
TOML_HEADER = "# granflow resolved configuration: rerun with `granflow run config.toml`\n"
MAX_TOML_BYTES = 2**20  # a configuration or sweep file is a few kB


class ConfigError(ValueError):
    """Invalid configuration; the message is one line naming the key, value and allowed range."""


# Ranges a physical run can use (SI): wide enough for laboratory to field scales, narrow
# enough that no value overflows, underflows or makes Netgen mesh for hours.
Positive = Annotated[float, Field(gt=0)]
NonNegative = Annotated[float, Field(ge=0)]
Angle = Annotated[float, Field(ge=0, lt=90)]
Fraction = Annotated[float, Field(gt=0, lt=1)]
Length = Annotated[float, Field(gt=0, le=1e4)]           # m
Duration = Annotated[float, Field(gt=0, le=1e4)]         # s
Step = Annotated[float, Field(ge=1e-12, le=100)]         # s, a time step
Penalty = Annotated[float, Field(ge=1, le=1e20)]
Count = Annotated[int, Field(ge=0, le=10**9)]


class _Section(BaseModel):
    """Base of every model: frozen, strict types (no str -> float coercion), no extra keys."""

    model_config = ConfigDict(frozen=True, extra="forbid", strict=True, allow_inf_nan=False)

    @model_validator(mode="before")
    @classmethod
    def _unset_none(cls, data: Any) -> Any:
        # TOML has no null: the string "none" unsets an optional field. An integer written
        # as a float (1e3, 100.0) is that integer.
        if not isinstance(data, dict):
            return data
        return {
            k: None if _is_none(v) and k in cls.model_fields and _optional(cls, k)
            else int(v) if _integral(v) and k in cls.model_fields and _int_field(cls, k)
            else v
            for k, v in data.items()
        }


def _is_none(value: Any) -> bool:
    return isinstance(value, str) and value.lower() == "none"


def _optional(model: type[BaseModel], key: str) -> bool:
    return NoneType in get_args(model.model_fields[key].annotation)


def _integral(value: Any) -> bool:
    return (isinstance(value, float) and math.isfinite(value) and value.is_integer()
            and abs(value) < 2**63)


def _int_field(model: type[BaseModel], key: str) -> bool:
    tp = model.model_fields[key].annotation
    return tp is int or int in get_args(tp) or any(
        get_origin(a) is Annotated and get_args(a)[0] is int for a in get_args(tp))


class Material(_Section):
    density: Annotated[float, Field(ge=1, le=1e5)]  # rho (kg/m^3)
    viscosity: Annotated[float, Field(ge=1e-9, le=1e6)]  # dynamic viscosity eta (Pa s)
    friction_angle_deg: Angle  # delta, mu_s = tan(delta); 0 = the purely viscous limit
    rheology: Literal["drucker-prager", "mu-i"]
    gravity: Annotated[float, Field(gt=0, le=100)]  # g (m/s^2)
    mu_2_deg: Angle  # mu(I): mu_2 = tan(angle), the friction at large I
    i0: Annotated[float, Field(gt=0, le=100)]  # mu(I): I0
    grain_diameter: Annotated[float, Field(gt=0, le=10)]  # mu(I): d (m)
    grain_density: Annotated[float, Field(ge=1, le=1e5)]  # mu(I): rho_s (kg/m^3)

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
    length: Length  # periodic layer: length l
    height: Length  # layer height h, or column height h0
    shape: Literal["trapezoid", "rectangle"]  # column
    width: Length  # column BASE width l0 (the paper's l0; top width = l0 - h0 / tan(alpha0))
    front_angle_deg: Annotated[float, Field(gt=0, le=90)]  # column front angle alpha0
    erodible_thickness: Annotated[float, Field(ge=0, le=1e4)]  # column: he, 0 = rigid bed
    bed_length: Length  # column on an erodible layer: where the layer ends


class Boundary(_Section):
    bed_friction_deg: Angle  # Coulomb mu_b = tan(angle)
    wall_friction_deg: Angle  # Coulomb mu_l = tan(angle)
    penalty: Penalty  # enforces u.n = 0 on the bed and the wall
    normal_load: Literal["pressure", "reaction"]  # friction load: [p - sigma'_N]_+ or [xi u.N]_+
    channel_width: Annotated[float, Field(gt=0, le=1e4)] | None  # side walls W; None = none
    side_wall_friction_deg: Angle  # Coulomb mu_w = tan(angle) of the side walls

    @property
    def mu_bed(self) -> float:
        return math.tan(math.radians(self.bed_friction_deg))

    @property
    def mu_wall(self) -> float:
        return math.tan(math.radians(self.wall_friction_deg))


class Initial(_Section):
    shear_rate: Annotated[float, Field(ge=0, le=1e4)]  # plug flow: U0 = rate [Z - plug_base]_+
    plug_base: Annotated[float, Field(ge=0, le=1e4)]


class Mesh(_Section):
    size: Annotated[float, Field(gt=0, le=1e3)]  # target edge length (m)
    cells_x: Annotated[int, Field(ge=2, le=10**5)] | None  # periodic layer; None = length/size
    # column: cells across its smaller side (sets size = min(width, height) / cells_across)
    cells_across: Annotated[int, Field(ge=1, le=1000)] | None
    remesh_quality: Annotated[float, Field(ge=0, lt=1)]  # column: also remesh below; 0 = off
    failure_remesh_quality: Annotated[float, Field(ge=0, lt=1)]  # remesh a failed solve below
    layer_cells: Annotated[int, Field(ge=1, le=16)]  # cells across an erodible layer


class Numerics(_Section):
    eps: Annotated[float, Field(gt=0, le=1e3)]  # regularisation epsilon of (2.13) (1/s)
    eps_friction: Annotated[float, Field(gt=0, le=1e3)]  # of the Coulomb friction (m/s)
    tol: Annotated[float, Field(ge=1e-14, lt=1)]  # stopping tolerance of (3.2); >= round-off
    tol_init: Fraction | None  # start tolerance of the ramp; None = tol
    max_iterations: Annotated[int, Field(ge=1, le=10**5)]
    linearization: Literal["picard", "newton", "hybrid", "primal-dual"]
    mesh_velocity: Literal["fixed", "vertical", "elastic", "lagrange"]
    mesh_penalty: Penalty
    velocity_floor: Annotated[float, Field(ge=0, le=1e3)]  # m/s, floor of ||u|| in (3.2)
    volume_correction: bool  # restore the initial area after each ALE move (column only)
    ale_extrapolation: bool  # mesh velocity of the extrapolated mid-step velocity (2nd order)
    linear_solver: Literal["auto", "umfpack", "pardiso"]  # auto: PARDISO when MKL is there
    initial_guess: Literal["previous", "extrapolated", "auto"]  # first iterate of (3.2)
    method: Literal["regularized", "augmented-lagrangian"]  # (2.13) with eps, or ALG2
    al_r: Literal["auto"] | Annotated[float, Field(gt=0, le=1e12)]  # augmentation r (Pa s)

    @property
    def tol_start(self) -> float:
        return self.tol if self.tol_init is None else self.tol_init


class Time(_Section):
    t_end: Duration
    dt: Step | None  # fixed step; overrides the ramp
    dt_init: Step
    dt_max: Step
    dt_growth: Annotated[float, Field(ge=1, le=10)]
    adaptive: bool  # error-controlled steps; false keeps the paper's ramp (3.1)
    scheme: Literal["implicit-euler", "bdf2"]  # time scheme of (3.2a): order 1 or 2
    error_tol: Fraction  # adaptive: local velocity error per step / RMS speed
    error_floor: Annotated[float, Field(gt=0, le=1e3)]  # adaptive: m/s, RMS speed floor
    stop_at_rest: bool  # end the run once the mass has come to rest
    rest_fraction: Annotated[float, Field(ge=0, lt=1)]  # flowing area at rest, at most
    rest_duration: Annotated[float, Field(ge=0, le=1e4)]  # s at rest before the run ends
    output_times: list[float]


class SurfaceTension(_Section):
    enabled: bool
    delta: Annotated[float, Field(gt=0, le=1e4)]  # extent in surface nodes (3.11)
    gamma0: Literal["auto"] | Annotated[float, Field(ge=0, le=1e9)]  # gamma0-bar of (3.11)
    trigger_angle_deg: Annotated[float, Field(ge=0, le=180)]  # on where the surface turns >=
    release_angle_deg: Annotated[float, Field(ge=0, le=180)]  # stays on while it turns >=


class Output(_Section):
    vtk_every: Count  # 0 = only at output_times
    checkpoint_every: Count  # 0 = only when interrupted or failed
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

    @classmethod
    def load(cls, source: str | Path, overrides: Sequence[str] = ()) -> Config:
        """A built-in scenario or a TOML file, resolved and validated (``load_config``)."""
        return load_config(source, overrides)

    def set(self, key: str, value: Any) -> Config:
        """A new, validated configuration with ``key`` ("section.key") set to ``value``."""
        return apply_overrides(self, [f"{key}={toml_literal(value)}"])


SECTIONS: dict[str, type[_Section]] = {
    name: field.annotation
    for name, field in Config.model_fields.items()
    if isinstance(field.annotation, type) and issubclass(field.annotation, _Section)
}


# ---------------------------------------------------------------- loading and layering


def load_config(source: str | Path, overrides: Sequence[str] = ()) -> Config:
    """Resolve defaults -> scenario (built-in name or TOML file) -> ``--set`` overrides.

    A key the user sets (in a TOML file or with ``--set``) to something other than what it
    would be anyway is rejected when it has no effect on this scenario (``inert_keys``).
    """
    data = _defaults()
    name, layers = _read_source(source)
    from_file = name == CUSTOM or len(layers) > 1
    for layer in layers[:-1] if from_file else layers:
        _merge(data, layer)
    base = copy.deepcopy(data)
    if from_file:
        _merge(data, layers[-1])
    explicit = "output_times" in layers[-1].get("time", {}) if from_file else False
    _apply(data, overrides)
    _drop_late_outputs(data, overrides, explicit)
    data["scenario"] = name
    config = _validate(data)
    changed = [f"{section}.{key}" for section in SECTIONS for key in data[section]
               if data[section][key] != base[section].get(key)]
    inert = inert_keys(config)
    for key in changed:
        if key in inert:
            section, name_ = key.split(".")
            raise ConfigError(f"{key} = {_fmt(data[section][name_])} has no effect here: "
                              f"{inert[key]}; remove it")
    cells = config.mesh.cells_across
    if cells is not None and config.geometry.kind == "column":
        size = min(config.geometry.width, config.geometry.height) / cells
        if "mesh.size" in changed and not math.isclose(config.mesh.size, size):
            raise ConfigError(f"mesh.size = {config.mesh.size!r} and mesh.cells_across = "
                              f"{cells} both set the mesh size; set one of them")
        data["mesh"]["size"] = size      # the resolution follows the column
        config = _validate(data)
    return config


def _drop_late_outputs(data: dict[str, Any], overrides: Sequence[str], explicit: bool) -> None:
    """Inherited output times after a shortened t_end are dropped (not those the user set)."""
    explicit = explicit or any(o.partition("=")[0].strip() == "time.output_times"
                               for o in overrides)
    t_end, times = data["time"]["t_end"], data["time"]["output_times"]
    if not explicit and _numbers(times) and _numbers([t_end]):
        data["time"]["output_times"] = [x for x in times if x <= t_end]


def _numbers(values: Any) -> bool:
    return isinstance(values, list) and all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in values)



def apply_overrides(config: Config, overrides: Sequence[str]) -> Config:
    """A copy of ``config`` with ``section.key=value`` overrides applied and re-validated."""
    data = config.model_dump()
    _apply(data, overrides)
    _drop_late_outputs(data, overrides, explicit=False)
    return _validate(data)


def toml_literal(value: Any) -> str:
    """``value`` as the TOML literal an override reads (None unsets: "none")."""
    return '"none"' if value is None else tomli_w.dumps({"v": value}).partition("=")[2].strip()


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
        data = read_toml_file(path, "scenario file")
        _check_keys(data)
        base = data.pop("scenario", CUSTOM)
        if base == CUSTOM:
            return CUSTOM, [data]
        return base, [_builtin(base, where=f" (named by 'scenario' in {path})"), data]
    return text, [_builtin(text)]


def read_toml_file(path: Path, what: str) -> dict[str, Any]:
    """A user's TOML file, refused with a one-line ConfigError if it is not a regular file
    of at most 1 MB of UTF-8 TOML (a device such as /dev/zero is never read)."""
    try:
        if not path.is_file():
            raise ConfigError(f"{what} '{path}' not found" if not path.exists()
                              else f"{what} '{path}' is not a regular file")
        if path.stat().st_size > MAX_TOML_BYTES:
            raise ConfigError(f"{what} '{path}' is larger than {MAX_TOML_BYTES // 2**20} MB; "
                              "a configuration is a few kB")
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as err:
        raise ConfigError(f"cannot read {what} '{path}': {err}") from None
    except RecursionError:
        raise ConfigError(f"cannot read {what} '{path}': its arrays or tables are nested "
                          "too deeply") from None


def _builtin(name: Any, where: str = "") -> dict[str, Any]:
    names = builtin_scenarios()
    if not isinstance(name, str) or name not in names:
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
        raise ConfigError(one_line(err.errors()[0], data, SECTIONS)) from None
