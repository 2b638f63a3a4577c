"""``fields/``: the output writing VTU snapshots of the finite-element fields (at output
times, every ``output.vtk_every`` steps and at the last accepted state); the file format,
its index and its reader are ``io/vtk.py``.

What a snapshot holds of the flow is read through the ``FlowFields`` protocol (the flow's
own, ``diagnostics/flow_fields.py``: velocity and pressure at the vertices, the speed, the
strain rate, the viscosity, the stress and the yield ratio per triangle); then the cell
data the problem's parts declare (``simulation/outputs.py``): with a layer of its own
material layer_fraction (the share of layer material in each triangle), with a hysteretic
friction mobilisation (the state s of ``physics/hysteresis.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, ClassVar, NamedTuple, Protocol

import numpy as np

from granflow.io.run_dir import RunDir
from granflow.io.vtk import FOLDER, VtkSeries
from granflow.state.spec import TIME, Share, list_of, may_lack, text, tuple_of


class Snapshot(NamedTuple):
    """The fields of one snapshot: the vertices (n, dim) and triangles (m, 3) of the mesh,
    values per vertex and per triangle by name."""

    points: np.ndarray
    cells: np.ndarray
    point_data: dict[str, np.ndarray]
    cell_data: dict[str, np.ndarray]


class FlowFields(Protocol):
    """The flow as a snapshot reads it, on its current mesh (a remesh replaces it)."""

    def snapshot(self) -> Snapshot: ...


class FieldSnapshots:
    """The VTU series of a run; ``entries`` (time, file) is what a checkpoint remembers.
    ``cell_data``: the problem's own cell data (name -> one value per triangle)."""

    name = "fields"
    share: ClassVar[Share] = {"vtk_entries": may_lack(list_of(tuple_of(      # of a checkpoint
        TIME, text(r"fields_\d{5,9}\.vtu", "a snapshot's name fields_NNNNN.vtu"))))}

    def __init__(self, run_dir: RunDir, flow: FlowFields,
                 resume: Mapping[str, Any] | None = None,
                 cell_data: Callable[[], dict[str, np.ndarray]] | None = None) -> None:
        self.flow, self.cell_data = flow, cell_data
        self.series = VtkSeries(run_dir.path(FOLDER),
                                place=lambda name: run_dir.path(f"{FOLDER}/{name}"))
        self.series.entries = list(resume.get("vtk_entries", [])) if resume else []

    def write(self, t: float) -> None:
        """The flow's fields and the problem's own cell data at time t."""
        shot = self.flow.snapshot()
        own = self.cell_data() if self.cell_data is not None else {}
        self.series.write(t, shot.points, shot.cells, point_data=shot.point_data,
                          cell_data={**shot.cell_data, **own})

    def write_last(self, t: float) -> None:
        """A snapshot at ``t`` unless the last one already is at that time."""
        entries = self.series.entries
        if not entries or abs(entries[-1][0] - t) > 1e-12:
            self.write(t)

    def save_state(self) -> dict[str, Any]:
        return {"vtk_entries": list(self.series.entries)}
