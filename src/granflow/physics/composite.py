"""Composite laws unwrapped in one place. A column over a layer of its own material
(``regions.TwoMaterials``) and a hysteretic friction (``hysteresis.Hysteretic``) each blend
two laws, ``parts``, with a weight, ``share`` (``per_triangle``: its cell values): the first
part at weight 0, the second at 1. A law may also wrap one law, ``inner``, adding to its
friction (a packing fraction's dilatancy, ``packing.Dilatant``). Whoever needs a value of
the simple laws inside a law (the yield stress, the primal-dual slope, the mobilisation's
cells, whether every part is Drucker-Prager) asks here, never with isinstance on a
composite or a wrapper.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from granflow.physics.regions import blend


def composites(law: Any) -> Iterator[Any]:
    """``law`` and the laws inside it that blend two laws (those with ``parts``), outer
    first, through any wrapper."""
    if hasattr(law, "inner"):
        yield from composites(law.inner)
    elif hasattr(law, "parts"):
        yield law
        for part in law.parts:
            yield from composites(part)


def simple_laws(law: Any) -> Iterator[Any]:
    """The laws that ``law`` blends, down to those that blend nothing, unwrapped."""
    if hasattr(law, "inner"):
        yield from simple_laws(law.inner)
    elif hasattr(law, "parts"):
        for part in law.parts:
            yield from simple_laws(part)
    else:
        yield law


def share(composite: Any) -> Any:
    """The weight of a composite's second part where the law is evaluated."""
    return composite.share


def cell_share(composite: Any) -> Any:
    """The weight per triangle, as an array (the engine's vector of cell values)."""
    return composite.per_triangle.vec.FV().NumPy()


def blended(law: Any, value: Callable[[Any], Any],
            weight: Callable[[Any], Any] = share,
            added: Callable[[Any], Any] | None = None) -> Any:
    """``value`` of each simple law inside ``law``, blended as ``law`` blends them: a
    composite's first part at weight 0, its second at weight 1; a wrapper gives its inner
    law's, plus ``added(wrapper)`` where that is given."""
    if hasattr(law, "inner"):
        inner = blended(law.inner, value, weight, added)
        return inner if added is None else inner + added(law)
    if not hasattr(law, "parts"):
        return value(law)
    first, second = law.parts
    return blend(blended(first, value, weight, added), blended(second, value, weight, added),
                 weight(law))
