"""The share of layer material in each triangle, for a column over an erodible layer of a
material of its own: the field that blends the two materials' laws and densities
(``physics/regions.py``) and a nonlocal law's coefficients (``fem/fluidity.py``). It is
filled from the tracked layer region on every mesh (``scenarios/column_discretisation.py``).

A plain L2 function is 0 on a boundary element: the walls read the adjacent triangle's value
(``fem/engine.py: read_on_walls``), the volume the function itself.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs

from granflow.fem.coupling import Coupling, Site


@dataclass(frozen=True)
class MaterialShareSpec:
    """Two materials in the run: a share field on each of its meshes."""

    def build(self, site: Site, fields: Mapping[str, Any]) -> MaterialShare:
        return MaterialShare(ngs.GridFunction(ngs.L2(site.mesh, order=0)))


class MaterialShare(Coupling):
    """The piecewise constant share of layer material, which the law reads."""

    name = "material-share"

    def __init__(self, fraction: ngs.GridFunction) -> None:
        self.fraction = fraction

    def law_fields(self) -> Mapping[str, Any]:
        return {"share": self.fraction}
