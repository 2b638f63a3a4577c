"""``fields/``: the output writing VTU snapshots of the finite-element fields (at output
times, every ``output.vtk_every`` steps and at the last accepted state); the file format,
its index and its reader are ``io/vtk.py``.

Point data: velocity (m/s), pressure (Pa). Cell data (means over each triangle): speed
(m/s), strain_rate_norm (1/s), effective_viscosity (Pa s), the flowing flag (speed above
1 mm/s), the stress stress_xx, stress_zz, stress_xz (and stress_hoop for a cylinder) and
deviatoric_stress_norm (Pa), and yield_ratio (``diagnostics/stress.py``); then the cell
data the problem's parts declare (``simulation/outputs.py``): with a layer of its own
material layer_fraction (the share of layer material in each triangle), with a hysteretic
friction mobilisation (the state s of ``physics/hysteresis.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, ClassVar, Protocol

import ngsolve as ngs
import numpy as np

from granflow.diagnostics.state import FLOWING_SPEED
from granflow.diagnostics.stress import static_yield_stress, stress_components, yield_ratio
from granflow.fem.flow import FlowSolver
from granflow.fem.sampling import cell_means, triangles, vertex_samples
from granflow.io.run_dir import RunDir
from granflow.io.vtk import FOLDER, VtkSeries
from granflow.simulation.state_spec import TIME, Share, list_of, may_lack, text, tuple_of


class FlowState(Protocol):
    """Where the current mesh and flow live (a remesh replaces both)."""

    mesh: ngs.Mesh
    solver: FlowSolver


class FieldSnapshots:
    """The VTU series of a run; ``entries`` (time, file) is what a checkpoint remembers.
    ``cell_data``: the problem's own cell data (name -> one value per triangle)."""

    name = "fields"
    share: ClassVar[Share] = {"vtk_entries": may_lack(list_of(tuple_of(      # of a checkpoint
        TIME, text(r"fields_\d{5,9}\.vtu", "a snapshot's name fields_NNNNN.vtu"))))}

    def __init__(self, run_dir: RunDir, state: FlowState,
                 resume: Mapping[str, Any] | None = None,
                 cell_data: Callable[[], dict[str, np.ndarray]] | None = None) -> None:
        self.state, self.cell_data = state, cell_data
        self.series = VtkSeries(run_dir.path(FOLDER),
                                place=lambda name: run_dir.path(f"{FOLDER}/{name}"))
        self.series.entries = list(resume.get("vtk_entries", [])) if resume else []

    def write(self, t: float) -> None:
        """Velocity, pressure, |Du|, effective viscosity, the flowing flag, the stress and
        the yield ratio at time t."""
        solver, mesh = self.state.solver, self.state.mesh
        speed, _ = cell_means(mesh, ngs.Norm(solver.velocity))
        own = self.cell_data() if self.cell_data is not None else {}
        stress = {name: cell_means(mesh, cf)[0]
                  for name, cf in stress_components(solver).items()}
        kappa = cell_means(mesh, static_yield_stress(solver.rheology, solver.pressure))[0]
        stress["yield_ratio"] = yield_ratio(stress["deviatoric_stress_norm"], kappa)
        self.series.write(
            t, mesh.ngmesh.Coordinates().copy(), triangles(mesh),
            point_data={"velocity": vertex_samples(mesh, solver.velocity),
                        "pressure": vertex_samples(mesh, solver.pressure)},
            cell_data={"flowing": (speed > FLOWING_SPEED).astype(float), "speed": speed,
                       "strain_rate_norm": cell_means(mesh, solver.strain_rate_norm())[0],
                       "effective_viscosity":
                           cell_means(mesh, solver.effective_viscosity())[0],
                       **stress, **own})

    def write_last(self, t: float) -> None:
        """A snapshot at ``t`` unless the last one already is at that time."""
        entries = self.series.entries
        if not entries or abs(entries[-1][0] - t) > 1e-12:
            self.write(t)

    def save_state(self) -> dict[str, Any]:
        return {"vtk_entries": list(self.series.entries)}
