"""Walls whose u.N = 0 the velocity space holds (``fem/spaces.py``: a component held at 0
on a region), kept in step with the boundary labels: deposition relabels a surface
triangle that lands on a wall (``ale/channel_mover.py``), which must then hold its normal
velocity as the penalty (2.7) would. At the start of each step, if a label changed (on
any rank), the space recomputes its free degrees of freedom, the nonlinear solver's
systems take them (a fresh factorisation) and the first iterate's newly held values
are set to 0 (Newton keeps what a correction does not touch)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.fem.coupling import Coupling, Flow, Site


@dataclass(frozen=True)
class HeldWallsSpec:
    """The coupling of a flow whose space holds u.N = 0 on its walls."""

    def build(self, site: Site, fields: Mapping[str, Any]) -> HeldWalls:
        return HeldWalls()


class HeldWalls(Coupling):
    """The space's held components follow the boundary labels (module docstring)."""

    name = "held_walls"

    def __init__(self) -> None:
        self._flow: Flow | None = None
        self._labels = np.empty(0, dtype=np.int64)

    def bind(self, flow: Flow) -> None:
        self._flow = flow
        self._labels = self._read()

    def _read(self) -> np.ndarray:
        assert self._flow is not None
        return self._flow.mesh.ngmesh.Elements2D().NumPy()["index"].astype(np.int64)

    def start_step(self, dt: float) -> None:
        flow = self._flow
        assert flow is not None
        labels = self._read()
        changed = int(not np.array_equal(labels, self._labels))
        if flow.mesh.comm.size > 1:             # every rank updates its space together
            changed = flow.mesh.comm.Max(changed)
        if not changed:
            return
        self._labels = labels
        for space in (flow.space.components[0], flow.space):   # the velocity's first
            space.Update()
            space.FinalizeUpdate()            # the free dofs from the new labels
        free = flow.space.FreeDofs()
        flow.nonlinear.set_free_dofs(free)
        held = ~np.array(list(free), dtype=bool)
        held[flow.space.components[0].ndof:] = False     # the pressure is never held
        flow.solution.vec.FV().NumPy()[held] = 0.0


def held_dofs(space: ngs.FESpace) -> np.ndarray:
    """The velocity degrees of freedom that are not free (a test's view)."""
    held = ~np.array(list(space.FreeDofs()), dtype=bool)
    held[space.components[0].ndof:] = False
    return held
