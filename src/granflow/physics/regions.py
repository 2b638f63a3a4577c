"""Two materials in one flow: a column over a bed layer of its own material.

``fraction`` is the share of layer material at a point (the material indicator: per
triangle, the area inside the tracked layer region, ``geometry/layer_material.py``); the law
is the column's where it is 0 and the layer's where it is 1. Blending the factor ``m`` of
sigma' = m Du (2.13) is choosing the law per triangle wherever a triangle holds one material,
and a mixture rule (the area-weighted stresses) in the few triangles the interface crosses.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

from granflow.physics.ops import NUMPY_OPS, Ops
from granflow.physics.rheology import Rheology


def blend(column: Any, layer: Any, fraction: Any) -> Any:
    """column + fraction (layer - column): a value that is the column's at 0, the layer's
    at 1 (numbers, arrays or FE coefficient functions alike)."""
    return column + fraction * (layer - column)


@dataclass(frozen=True)
class TwoMaterials:
    """The ``Rheology`` of a column (``column``) over a layer (``layer``): ``fraction`` is
    the share of layer material where the law is evaluated, ``per_triangle`` its values
    triangle by triangle for the consumers that work on arrays (an object with the
    finite-element engine's ``vec``; ``fem/primal_dual.py``, ``io/fields.py``)."""

    column: Rheology
    layer: Rheology
    fraction: Any
    per_triangle: Any = None

    @property
    def parts(self) -> tuple[Rheology, Rheology]:
        """At a fraction 0 the column's law, at 1 the layer's (``physics/composite.py``)."""
        return self.column, self.layer

    @property
    def share(self) -> Any:
        return self.fraction

    @property
    def viscosity(self) -> Any:
        return blend(self.column.viscosity, self.layer.viscosity, self.fraction)

    def with_fields(self, read: Callable[[Any], Any]) -> TwoMaterials:
        """The law with the fields it holds per triangle (the share, and those of its two
        laws) passed through ``read`` (on a wall: taken from the adjacent triangle)."""
        return replace(self, column=_with_fields(self.column, read),
                       layer=_with_fields(self.layer, read), fraction=read(self.fraction))

    @property
    def eps(self) -> float:
        return self.column.eps     # type: ignore[attr-defined,no-any-return]

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        return blend(self.column.effective_viscosity_sq(strain_rate_sq, pressure, ops),
                     self.layer.effective_viscosity_sq(strain_rate_sq, pressure, ops),
                     self.fraction)

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)


def _with_fields(law: Rheology, read: Callable[[Any], Any]) -> Rheology:
    with_fields = getattr(law, "with_fields", None)
    return law if with_fields is None else with_fields(read)  # type: ignore[no-any-return]
