"""Material presets in the configuration's layers (the constants: ``physics/presets.py``).

``material.preset = "glass-beads"`` (``layer.preset`` for an erodible layer's own material)
sets every constant of the material for the law it runs with. A value the user writes wins:
whatever is set in the layer that names the preset or after it (the user's TOML file, the
``--set`` overrides, ``Config.set``). The preset's values also count as what the keys
would be without the user's settings, so that none of them is refused as a key without
effect. A law that runs with the friction angle another law's constants go with (mu(I) or
the nonlocal law at the Drucker-Prager 25.5 deg rather than 20.9) gets a one-line note.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from typing import Any

from granflow.config.kinds import erodible_layer
from granflow.config.schema import ConfigModel
from granflow.physics.presets import PRESETS, Preset

SECTIONS = ("material", "layer")     # the sections that hold a material
Raw = dict[str, Any]


def user_keys(layers: Sequence[Mapping[str, Any]], overrides: Iterable[str]
              ) -> dict[str, set[str]]:
    """For each section whose preset is named: the "section.key" names set in the layer that
    names it and in every later one (the overrides last), which win over the preset."""
    stack = [{f"{s}.{k}" for s, table in layer.items() if isinstance(table, dict)
              for k in table} for layer in layers]
    stack.append(set(overrides))
    out: dict[str, set[str]] = {}
    for section in SECTIONS:
        named = [i for i, keys in enumerate(stack) if f"{section}.preset" in keys]
        if named:
            out[section] = set().union(*stack[named[-1]:])
    return out


def changed_keys(config: ConfigModel, overrides: Iterable[str]) -> dict[str, set[str]]:
    """``user_keys`` for a resolved configuration changed by ``overrides``: those, and every
    key that held another value than its preset gave it (set by the user then)."""
    out = {}
    for section in SECTIONS:
        before = getattr(config, section)
        preset = PRESETS.get(before.preset or "")
        law = _law(config.model_dump(), section)
        kept = set() if preset is None or law is None else {
            f"{section}.{k}" for k, v in preset.values(*law).items()
            if getattr(before, k) != v}
        out[section] = kept | set(overrides)
    return out


def apply_presets(data: Raw, base: Raw, kept: Mapping[str, set[str]]) -> None:
    """Set each named preset's values into ``data`` (but the keys in ``kept``) and into
    ``base``. A preset or a law the schema does not know is left to the validation."""
    for section in SECTIONS:
        preset = PRESETS.get(str(data[section].get("preset")))
        law = _law(data, section)
        if preset is None or law is None:
            continue
        for key, value in preset.values(*law).items():
            base[section][key] = value
            if f"{section}.{key}" not in kept.get(section, ()):
                data[section][key] = value


def _law(data: Raw, section: str) -> tuple[str, str] | None:
    """The rheology and friction of a section's material (a layer's: [material]'s where it
    sets none), if they are names of laws."""
    names = []
    for key in ("rheology", "friction"):
        value = data[section].get(key)
        if section == "layer" and value in (None, "none"):
            value = data["material"].get(key)
        names.append(value)
    return (names[0], names[1]) if all(isinstance(n, str) for n in names) else None


def mixed_constants(config: ConfigModel, user: set[str]) -> Iterator[str]:
    """A note for each material of the run whose law runs at the friction angle a preset
    gives another law, while its own constants are that preset's and the user did not choose
    the angle (mu(I) at 25.5 deg, whose glass-bead mu_2 and I0 go with 20.9)."""
    materials = {"material": config.material}
    if erodible_layer(config):
        own = {k: v for k, v in config.layer.model_dump().items() if v is not None}
        materials["layer"] = config.material.model_copy(update=own)
    for section, mat in materials.items():
        chosen = {f"{section}.friction_angle_deg", "material.friction_angle_deg"}
        if chosen & user or getattr(config, section).preset is not None:
            continue
        for preset in PRESETS.values():
            line = _mixed(section, mat, preset)
            if line:
                yield line
                break


def _mixed(section: str, mat: Any, preset: Preset) -> str | None:
    """The note for one material and one preset, or None."""
    own = preset.angle_by_rheology.get(mat.rheology)
    angle = mat.friction_angle_deg
    others = [law for law, a in preset.angle_by_rheology.items()
              if a == angle and law != mat.rheology]
    fitted = preset.fitted_with_angle.get(mat.rheology, ())
    if own is None or angle == own or not others or any(
            getattr(mat, k) != preset.shared[k] for k in fitted):
        return None
    theirs = (" and ".join(f"{k} = {preset.shared[k]:g}" for k in fitted) + " go with"
              if fitted else "its angle is")
    return (f"{section}.rheology = {mat.rheology!r} runs with {section}.friction_angle_deg = "
            f"{angle:g}, the {preset.name} preset's angle for {others[0]!r}; {theirs} "
            f"{own:g} (set {section}.preset = {preset.name!r} for all of them, or set the "
            "angle)")
