"""Composite laws unwrapped in one place. A column over a layer of its own material
(``regions.TwoMaterials``) and a hysteretic friction (``hysteresis.Hysteretic``) each blend
two laws, ``parts``, with a weight, ``share`` (``per_triangle``: its cell values): the first
part at weight 0, the second at 1. Whoever needs a value of the simple laws inside a law
(the yield stress, the primal-dual slope, the mobilisation's cells, whether every part is
Drucker-Prager) asks here, never with isinstance on a composite.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from granflow.physics.regions import blend


def composites(law: Any) -> Iterator[Any]:
    """``law`` and the laws inside it that blend two laws (those with ``parts``), outer
    first."""
    if hasattr(law, "parts"):
        yield law
        for part in law.parts:
            yield from composites(part)


def simple_laws(law: Any) -> Iterator[Any]:
    """The laws that ``law`` blends, down to those that blend nothing."""
    if hasattr(law, "parts"):
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
            weight: Callable[[Any], Any] = share) -> Any:
    """``value`` of each simple law inside ``law``, blended as ``law`` blends them: a
    composite's first part at weight 0, its second at weight 1."""
    if not hasattr(law, "parts"):
        return value(law)
    first, second = law.parts
    return blend(blended(first, value, weight), blended(second, value, weight), weight(law))
