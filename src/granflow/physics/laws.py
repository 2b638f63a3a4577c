"""The laws as a configuration names them. Each law registers whole, at the end of its own
module: the value that selects it (``material.rheology``, ``material.friction`` for a
friction that wraps the flow law, or ``material.packing`` for a packing fraction that wraps
both and sets the bulk density), the keys of ``[material]`` (and ``[layer]``) that only it
reads with their types, ranges, defaults and meaning (``Key``), the other keys it reads, its
checks of one material and how it is built from a material's keys; a 1D reference of a
periodic layer, where it has one, is attached to it by the reference's module
(``register_reference``). The configuration's schema, rules and parameters page
(``config/``), the builders (``scenarios/materials.py``) and the periodic layer's reference
read this registry and name no law. A material is any object with the keys as attributes
(the configuration's ``Material``); a check yields one line per problem, naming the key.

Composite laws are unwrapped in ``composite.py``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import Any


@dataclass(frozen=True)
class LawFields:
    """The fields a law may read where it is evaluated: the nonlocal fluidity g, the
    mobilisation s of a hysteretic friction and s per triangle, the share of layer
    material per triangle that blends two materials, and the packing fraction's departure
    from each material's initial packing per triangle (engine objects or numbers; the
    fields coupled to the flow hand them, ``fem/coupling.py``)."""

    fluidity: Any = 0.0
    mobilisation: Any = 0.0
    per_triangle: Any = None
    share: Any = None
    packing: Any = None


@dataclass(frozen=True)
class Key:
    """A key of ``[material]`` (and, unset by default, of ``[layer]``) that a law reads:
    its default, its meaning (one line, for the parameters page), its range (``low`` <=
    value <= ``high``, ``above`` < value < ``below``; ``floor``: why ``low`` is the
    smallest physical value of a key whose natural bound is 0) and the words it accepts
    besides a number (``choices``)."""

    default: float | str
    words: str
    low: float | None = None
    high: float | None = None
    above: float | None = None
    below: float | None = None
    floor: str = ""
    choices: tuple[str, ...] = ()


def _no_checks(material: Any, section: str, eps: float) -> Iterator[str]:
    return iter(())


@dataclass(frozen=True)
class Law:
    """A flow law (``build(material, eps, fields)``), or a friction or a packing that wraps
    one (``build(material, eps, fields, flow)``): its own keys, the keys of other laws or of
    every material it also reads (``reads``), the keys of other sections only it uses
    (``settings``, "section.key"), its checks of a material (``checks(material, section,
    eps)``, eps the regularisation of (2.13)), whether its field crosses the interface of
    two materials (``one_field``: both must follow it), how messages name it (``words``),
    the bulk density it gives a material (``density(material, fields)``; None:
    ``material.density``) and its 1D reference of a periodic layer (attached by
    ``register_reference``)."""

    name: str
    keys: Mapping[str, Key]
    build: Callable[..., Any]
    checks: Callable[[Any, str, float], Iterator[str]] = _no_checks
    reads: tuple[str, ...] = ()
    settings: tuple[str, ...] = ()
    one_field: bool = False
    words: str = ""
    density: Callable[[Any, LawFields], Any] | None = None
    reference: Any = field(default=None, compare=False)

    @property
    def described(self) -> str:
        return self.words or f"the {self.name!r} law"


RHEOLOGIES: dict[str, Law] = {}     # by material.rheology
FRICTIONS: dict[str, Law] = {}      # by material.friction
PACKINGS: dict[str, Law] = {}       # by material.packing
REGISTERED = [0]   # registrations so far: the configuration's schema follows their count


def _register(table: dict[str, Law], law: Law) -> Law:
    for key, spec in law.keys.items():    # a key two laws read is declared alike
        other = next((o.keys[key] for o in all_laws() if key in o.keys), spec)
        if other != spec:
            raise ValueError(f"the law {law.name!r} declares {key!r} unlike another law")
    table[law.name] = law
    REGISTERED[0] += 1
    return law


def register_rheology(law: Law) -> Law:
    return _register(RHEOLOGIES, law)


def register_friction(law: Law) -> Law:
    return _register(FRICTIONS, law)


def register_packing(law: Law) -> Law:
    return _register(PACKINGS, law)


def register_reference(name: str, reference: Any) -> None:
    """Attach a 1D reference of a periodic layer to the law registered as ``name``."""
    table = next(t for t in (RHEOLOGIES, FRICTIONS, PACKINGS) if name in t)
    table[name] = dataclasses.replace(table[name], reference=reference)


def selecting_key(law: Law) -> str:
    """The key of a material that selects ``law``: rheology, friction or packing."""
    for key, table in (("rheology", RHEOLOGIES), ("friction", FRICTIONS),
                       ("packing", PACKINGS)):
        if table.get(law.name) is law:
            return key
    raise KeyError(law.name)


def described(material: Any) -> str:
    """A material's laws as a message names them: its rheology, and its friction and
    packing where they are not the defaults."""
    return f"rheology = {material.rheology!r}" + (
        f" with friction = {material.friction!r}" if material.friction != "constant"
        else "") + (f" with packing = {material.packing!r}" if material.packing != "none"
                    else "")


def all_laws() -> list[Law]:
    """Every registered law: the rheologies, the frictions, then the packings."""
    return [*RHEOLOGIES.values(), *FRICTIONS.values(), *PACKINGS.values()]


def laws_of(material: Any) -> tuple[Law, Law, Law]:
    """A material's rheology, friction and packing."""
    return (RHEOLOGIES[material.rheology], FRICTIONS[material.friction],
            PACKINGS[material.packing])


def law_keys() -> dict[str, Key]:
    """Every law's own keys, in the order the laws registered."""
    return {k: spec for law in all_laws() for k, spec in law.keys.items()}


def keys_read(material: Any) -> set[str]:
    """The law keys a material's rheology and friction read."""
    return {k for law in laws_of(material) for k in (*law.keys, *law.reads)}


def material_law(material: Any, eps: float, fields: LawFields = LawFields()) -> Any:
    """The law of one material: its rheology, wrapped by its friction and its packing."""
    flow = RHEOLOGIES[material.rheology].build(material, eps, fields)
    return packed(material, eps, fields,
                  FRICTIONS[material.friction].build(material, eps, fields, flow))


def packed(material: Any, eps: float, fields: LawFields, law: Any) -> Any:
    """``law`` (a material's rheology with its friction) wrapped by its packing."""
    return PACKINGS[material.packing].build(material, eps, fields, law)


def bulk_density(material: Any, fields: LawFields = LawFields()) -> Any:
    """The bulk density of a material: ``material.density``, or its packing's."""
    density = PACKINGS[material.packing].density
    return material.density if density is None else density(material, fields)


def checks(material: Any, section: str, eps: float) -> Iterator[str]:
    """What the material's rheology, friction and packing say is wrong with it."""
    for law in laws_of(material):
        yield from law.checks(material, section, eps)


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


register_friction(Law("constant", {}, lambda material, eps, fields, flow: flow,
                      words="a constant friction"))
register_packing(Law("none", {}, lambda material, eps, fields, flow: flow,
                     words="no packing fraction (incompressible)"))
