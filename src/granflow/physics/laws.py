"""The laws as a configuration names them. Each law registers, at the end of its own module,
the value that selects it (``material.rheology``, or ``material.friction`` for a friction
that wraps the flow law), the keys of ``[material]`` (and ``[layer]``) that only it reads,
its checks of one material, and how it is built from a material's keys; the configuration
(``config/rules.py``) and the builders (``scenarios/materials.py``) read this registry and
name no law. A material is any object with the keys as attributes (the configuration's
``Material``); a check yields one line per problem, naming the key.

Composite laws are unwrapped in ``composite.py``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class LawFields:
    """The fields a law may read where it is evaluated: the nonlocal fluidity g, the
    mobilisation s of a hysteretic friction and s per triangle, and the share of layer
    material per triangle that blends two materials (engine objects or numbers; the fields
    coupled to the flow hand them, ``fem/coupling.py``)."""

    fluidity: Any = 0.0
    mobilisation: Any = 0.0
    per_triangle: Any = None
    share: Any = None


def _no_checks(material: Any, section: str) -> Iterator[str]:
    return iter(())


@dataclass(frozen=True)
class Law:
    """A flow law (``build(material, eps, fields)``) or a friction that wraps one
    (``build(material, eps, fields, flow)``), with its own keys and its checks."""

    name: str
    keys: tuple[str, ...]
    build: Callable[..., Any]
    checks: Callable[[Any, str], Iterator[str]] = _no_checks


RHEOLOGIES: dict[str, Law] = {}     # by material.rheology
FRICTIONS: dict[str, Law] = {}      # by material.friction


def register_rheology(law: Law) -> Law:
    RHEOLOGIES[law.name] = law
    return law


def register_friction(law: Law) -> Law:
    FRICTIONS[law.name] = law
    return law


def material_law(material: Any, eps: float, fields: LawFields = LawFields()) -> Any:
    """The law of one material: its rheology, wrapped by its friction."""
    flow = RHEOLOGIES[material.rheology].build(material, eps, fields)
    return FRICTIONS[material.friction].build(material, eps, fields, flow)


def checks(material: Any, section: str) -> Iterator[str]:
    """What the material's rheology and friction say is wrong with it."""
    yield from RHEOLOGIES[material.rheology].checks(material, section)
    yield from FRICTIONS[material.friction].checks(material, section)


def named(section: str, key: str, words: str, value: Any) -> str:
    """Another key of the same material in a message: ``material.density = 1550.0``, or for
    the layer (whose value may be [material]'s) ``the layer's density 1550.0``."""
    return f"{section}.{key} = {value!r}" if section == "material" else (
        f"the layer's {words} {value!r}")


def packing_checks(material: Any, section: str) -> Iterator[str]:
    """Grains at least as dense as the bulk (a law that reads both)."""
    if material.grain_density < material.density:
        yield (f"{section}.grain_density = {material.grain_density!r} must be at least "
               f"{named(section, 'density', 'density', material.density)} (their ratio is "
               "the packing fraction)")


register_friction(Law("constant", (), lambda material, eps, fields, flow: flow))
