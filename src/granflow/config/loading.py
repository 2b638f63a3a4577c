"""Configuration: frozen, validated parameter models and their layered loading.

Layers, each overriding the one before (pyro2-style):

1. package defaults, ``granflow/defaults.toml`` (the one place where defaults live);
2. a scenario: a built-in name, or a TOML file, which may start from a built-in one with a
   top-level ``scenario = "NAME"``;
   a material preset (``material.preset``, ``layer.preset``) sets its constants over the
   layers below the one that names it (``presets.py``);
3. overrides: ``--set section.key=value`` texts, the value read as a TOML literal
   (``1e-4``, ``true``, ``[0.1, 0.2]``, ``"newton"``) or else as a bare string; or, from
   Python, a mapping ``{"section.key": value}`` of Python values.

TOML has no null, so an optional value is unset with the string ``"none"`` (None from
Python). Every path (a TOML file, ``--set``, ``Config.load``, ``Config.set``) ends in the same
checks (``_resolve``): unknown keys, out-of-range values, inconsistent combinations and keys
set where they have no effect raise :class:`ConfigError`, whose message is one line naming
the key, the value and what is allowed. Units are SI, angles in degrees.
"""

from __future__ import annotations

import copy
import math
import numbers
import tomllib
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import tomli_w
from pydantic import ValidationError, model_validator
from pydantic_core import PydanticCustomError

from granflow.config.kinds import KIND_RULES, absolute_paths, anchor_paths, rules_of
from granflow.config.messages import fmt_value, note, one_line
from granflow.config.presets import apply_presets, changed_keys, mixed_constants, user_keys
from granflow.config.rules import inert_keys, problems
from granflow.config.scenario_files import builtin_scenarios, scenario_text
from granflow.config.schema import SECTIONS, ConfigError, ConfigModel, law_sections
from granflow.physics.laws import law_keys

CUSTOM = "custom"  # scenario name of a TOML file that starts from the package defaults only
TOML_HEADER = "# granflow resolved configuration: rerun with `granflow run config.toml`\n"
MAX_TOML_BYTES = 2**20  # a configuration or sweep file is a few kB

# ["section.key=value", ...] (the command line's --set) or {"section.key": value} (Python)
Overrides = Mapping[str, Any] | Sequence[str]


class Config(ConfigModel):
    """The fully resolved configuration of one run."""

    @model_validator(mode="after")
    def _consistent(self) -> Config:
        for problem in problems(self):
            raise PydanticCustomError("granflow_config", "{message}", {"message": problem})
        return self

    @classmethod
    def load(cls, source: str | Path, overrides: Overrides = ()) -> Config:
        """A built-in scenario or a TOML file with ``overrides`` ({"section.key": value} or
        ["section.key=value", ...]), resolved and validated (``load_config``)."""
        return load_config(source, overrides)

    def set(self, key: str, value: Any) -> Config:
        """A new, validated configuration with ``key`` ("section.key") set to ``value``
        (None unsets an optional key); refused as the command line refuses ``--set``."""
        return apply_overrides(self, {key: value})

    def to_toml(self) -> str:
        """Every key as TOML: ``granflow run FILE`` and ``Config.load(FILE)`` read it back."""
        return config_to_toml(self)

    def save(self, path: str | Path) -> Path:
        """Write ``to_toml()`` to ``path`` (a .toml file, replaced if it exists)."""
        target = Path(path)
        if target.is_dir():
            raise ConfigError(f"cannot save the configuration to '{target}': it is a folder; "
                              "give a file name such as config.toml")
        try:
            target.write_text(self.to_toml(), encoding="utf-8")
        except OSError as err:
            raise ConfigError(f"cannot save the configuration to '{target}': "
                              f"{err.strerror or err}") from None
        return target

    def __repr__(self) -> str:
        g, t = self.geometry, self.time
        what = rules_of(self).describe(self)
        slope = f", slope {g.slope_deg:g} deg" if g.slope_deg else ""
        return (f"granflow.Config({self.scenario!r}: {what}{slope}, {self.material.rheology}, "
                f"t_end = {t.t_end:g} s; every key: .to_toml())")

    __str__ = __repr__


def load_config(source: str | Path, overrides: Overrides = ()) -> Config:
    """Resolve defaults -> scenario (built-in name or TOML file) -> overrides.

    A key the user sets (in a TOML file or an override) to something other than what it
    would be anyway is rejected when it has no effect on this scenario (``inert_keys``).
    """
    law_sections()
    data = _defaults()
    name, layers = _read_source(source)
    from_file = name == CUSTOM or len(layers) > 1
    for layer in layers[:-1] if from_file else layers:
        _merge(data, layer)
    base = copy.deepcopy(data)
    if from_file:
        _merge(data, layers[-1])
    explicit = "output_times" in layers[-1].get("time", {}) if from_file else False
    keys = _apply(data, overrides)
    data["scenario"] = name
    apply_presets(data, base, user_keys(layers, keys))
    user = set(keys) | ({f"{s}.{k}" for s, t in layers[-1].items() if isinstance(t, dict)
                         for k in t} if from_file else set())
    return _resolve(data, base, explicit or "time.output_times" in keys, user)


def apply_overrides(config: Config, overrides: Overrides) -> Config:
    """A copy of ``config`` with overrides applied, checked as ``load_config`` checks them
    (a key without effect here is refused when its value changes)."""
    law_sections()
    data = config.model_dump()
    base = copy.deepcopy(data)
    keys = _apply(data, overrides)
    apply_presets(data, base, changed_keys(config, keys))
    return _resolve(data, base, "time.output_times" in keys, set(keys))


def _resolve(data: dict[str, Any], base: dict[str, Any], explicit_times: bool,
             user: set[str]) -> Config:
    """The one validation path of every interface: ``data`` (the layers, the presets and
    the overrides merged) against ``base`` (what the keys would be without the user's
    settings, ``user``: the "section.key" names they set)."""
    dropped = _drop_late_outputs(data, explicit_times)
    absolute_paths(data)
    name = data["geometry"].get("kind")
    if isinstance(name, str) and name in KIND_RULES:     # else the schema says what is wrong
        KIND_RULES[name].prepare(data, base)
    config = _validate(data)
    changed = [f"{section}.{key}" for section in SECTIONS for key in data[section]
               if data[section][key] != base[section].get(key)]
    inert = inert_keys(config)
    for key in changed:
        if key in inert:
            section, name_ = key.split(".")
            raise ConfigError(f"{key} = {fmt_value(data[section][name_])} has no effect here: "
                              f"{inert[key]}; remove it")
    size = rules_of(config).derived_size(config)
    if size is not None:
        if "mesh.size" in changed and not math.isclose(config.mesh.size, size):
            raise ConfigError(f"mesh.size = {config.mesh.size!r} and mesh.cells_across = "
                              f"{config.mesh.cells_across} both set the mesh size; set one "
                              "of them")
        data["mesh"]["size"] = size      # the resolution follows the column
        config = _validate(data)
    for line in mixed_constants(config, user):
        note(line)
    if dropped:
        note(f"time.output_times {fmt_value(dropped)} of the scenario come after "
             f"time.t_end = {config.time.t_end:g} s and are not written (set "
             "time.output_times to choose others)")
    return config


def _drop_late_outputs(data: dict[str, Any], explicit: bool) -> list[float]:
    """Inherited output times after a shortened t_end are dropped (not those the user set);
    returns them."""
    t_end, times = data["time"]["t_end"], data["time"]["output_times"]
    if not explicit and _numbers(times) and _numbers([t_end]):
        data["time"]["output_times"] = [x for x in times if x <= t_end]
        return [x for x in times if x > t_end]
    return []


def _numbers(values: Any) -> bool:
    return isinstance(values, list) and all(
        isinstance(v, int | float) and not isinstance(v, bool) for v in values)



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
    """defaults.toml, and the defaults of the keys the laws register (``physics/laws.py``)."""
    text = resources.files("granflow").joinpath("defaults.toml").read_text(encoding="utf-8")
    data = tomllib.loads(text)
    _check_keys(data)
    out = {section: dict(data.get(section, {})) for section in SECTIONS}
    for key, spec in law_keys().items():
        out["material"].setdefault(key, spec.default)
        out["layer"].setdefault(key, "none")
    return out


def _read_source(source: str | Path) -> tuple[str, list[dict[str, Any]]]:
    """The scenario name and the TOML layers (base scenario first) that ``source`` stands for."""
    text = str(source)
    if isinstance(source, Path) or text.endswith(".toml") or "/" in text:
        path = Path(source)
        data = read_toml_file(path, "scenario file")
        _check_keys(data)
        anchor_paths(data, path.resolve().parent)
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
    except (OSError, ValueError) as err:   # also an integer of more than 4300 digits
        raise ConfigError(f"cannot read {what} '{path}': {err}") from None
    except RecursionError:
        raise ConfigError(f"cannot read {what} '{path}': its arrays or tables are nested "
                          "too deeply") from None


def _builtin(name: Any, where: str = "") -> dict[str, Any]:
    names = builtin_scenarios()
    if not isinstance(name, str) or name not in names:
        raise ConfigError(f"unknown scenario {fmt_value(name)}{where}; built-in scenarios: "
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
            raise ConfigError(f"'{section}' must be a table [{section}] of keys, "
                              f"not {fmt_value(table)}")
        known = SECTIONS[section].model_fields
        for key in table:
            if key not in known:
                raise ConfigError(f"unknown configuration key '{section}.{key}' "
                                  f"(known keys in [{section}]: {', '.join(known)})")


def _merge(data: dict[str, Any], layer: dict[str, Any]) -> None:
    for section, table in layer.items():
        data.setdefault(section, {}).update(table)


def _apply(data: dict[str, Any], overrides: Overrides) -> list[str]:
    """Set each override's key in ``data``; return the keys set. Texts are
    ``section.key=value`` with a TOML literal; a mapping holds Python values."""
    if isinstance(overrides, str):
        overrides = [overrides]
    items: list[tuple[str, Any]] = []
    if isinstance(overrides, Mapping):
        items = [(str(key).strip(), python_value(value)) for key, value in overrides.items()]
    else:
        for text in overrides:
            key, sep, raw = str(text).partition("=")
            if not sep or not key.strip():
                raise ConfigError(f"an override is section.key=value, got {text!r}")
            items.append((key.strip(), parse_value(raw)))
    for key, value in items:
        section, dot, name = key.partition(".")
        if not dot:
            raise ConfigError(f"unknown configuration key '{key}' (keys are section.key, "
                              f"sections: {', '.join(SECTIONS)})")
        _check_keys({section: {name: None}})
        data[section][name] = value
    return [key for key, _ in items]


def python_value(value: Any) -> Any:
    """A value given from Python as the configuration holds it: None unsets ("none"),
    numpy scalars and tuples become Python numbers and lists."""
    if value is None:
        return "none"
    if isinstance(value, bool | str):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, list | tuple) or (hasattr(value, "tolist") and callable(value.tolist)):
        items = value.tolist() if hasattr(value, "tolist") else value
        return [python_value(v) for v in items] if isinstance(items, list) else items
    return value


def parse_value(raw: str) -> Any:
    """A ``--set`` value: a TOML literal if it is one, else a Python float (``.5``, ``1.``),
    else the bare string (so ``--set numerics.linearization=newton`` needs no quotes)."""
    raw = raw.strip()
    try:
        parsed = tomllib.loads(f"v = {raw}")
    except ValueError:   # not TOML, or an integer of more than 4300 digits
        try:
            return float(raw)
        except ValueError:
            return raw
    return parsed["v"] if list(parsed) == ["v"] else raw


def _validate(data: dict[str, Any]) -> Config:
    try:
        return Config.model_validate(data)
    except ValidationError as err:
        raise ConfigError(one_line(err.errors()[0], data, SECTIONS)) from None
