"""The packing fraction of a critical-state law (``physics/packing.py``) in a problem: its
coupling to the flow (``fem/packing.py``: the dilatancy in the continuity row, moved and
relaxed with the flow, carried through remeshes and checkpoints; the column's free-surface
fix keeps its mass) and its outputs.

Its outputs (``simulation/outputs.py``): the diagnostics columns ``packing_mean`` (over
the mass's section, area- or in r-z volume-weighted), ``packing_min``, ``packing_max`` and
``mass_relative_error`` (the grains' mass against its value at t = 0); the cell data
``packing`` of the VTU snapshots (phi per triangle); in ``summary.json`` the final
``mass_relative_error``, its largest magnitude over the run ``mass_relative_error_max``
and the extremes of phi over the run, ``packing_min`` and ``packing_max``. The run's
``volume_relative_error`` is then the dilatancy's change of volume, not an error.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol

import numpy as np

from granflow.config import Config
from granflow.fem.flow import FlowSolver
from granflow.fem.packing import PackingCoupling, PackingSpec
from granflow.physics.packing import CRITICAL_STATE, critical_state
from granflow.scenarios.materials import RunMaterials
from granflow.simulation.outcomes import RunResult
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import Simulation
from granflow.state.spec import REAL, Share, may_lack, record


def packing_specs(config: Config, materials: RunMaterials) -> tuple[PackingSpec, ...]:
    """The packing of the run's materials (none unless they follow the critical-state law;
    the rules allow both materials or neither)."""
    if materials.column.packing != CRITICAL_STATE.name:
        return ()
    return (PackingSpec(tuple(critical_state(m, config.numerics.eps) for m in materials.all)),)


def packing_of(solver: FlowSolver) -> PackingCoupling | None:
    """The packing coupling of a solver, None without a packing law."""
    return solver.coupling(PackingCoupling)


class Host(Protocol):
    """Where the current flow solver lives (a collapse's remesh replaces it)."""

    solver: FlowSolver


@dataclass
class PackingOutputs(Outputs):
    """The packing's columns, cell data and summary (module docstring)."""

    columns = ("packing_mean", "packing_min", "packing_max", "mass_relative_error")
    share: ClassVar[Share] = {"packing_outputs": may_lack(record({
        "error_max": REAL, "low": REAL, "high": REAL}))}

    current: Host
    error_max: float = 0.0
    extremes: list[float] = field(default_factory=lambda: [1.0, 0.0])   # phi is in (0, 1)

    @classmethod
    def of(cls, current: Host) -> PackingOutputs | None:
        """The outputs of the packing of ``current``'s solver (None without one)."""
        return cls(current) if packing_of(current.solver) is not None else None

    @property
    def coupling(self) -> PackingCoupling:
        coupling = packing_of(self.current.solver)
        assert coupling is not None
        return coupling

    def mass_error(self) -> float:
        coupling = self.coupling
        return coupling.mass() / coupling.initial_mass() - 1.0

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        coupling, solver = self.coupling, self.current.solver
        packing = coupling.packing()
        measures = coupling.field.cell_measures(solver.mesh.ngmesh.Coordinates())
        error = self.mass_error()
        self.error_max = max(self.error_max, abs(error))
        self.extremes = [min(self.extremes[0], float(packing.min())),
                         max(self.extremes[1], float(packing.max()))]
        return {"packing_mean": float(np.sum(packing * measures) / np.sum(measures)),
                "packing_min": float(packing.min()), "packing_max": float(packing.max()),
                "mass_relative_error": error}

    def fields(self) -> dict[str, np.ndarray]:
        return {"packing": self.coupling.packing()}

    def summary(self, result: RunResult) -> dict[str, Any]:
        packing = self.coupling.packing()
        low = min(self.extremes[0], float(packing.min()))
        high = max(self.extremes[1], float(packing.max()))
        return {"mass_relative_error": self.mass_error(),
                "mass_relative_error_max": max(self.error_max, abs(self.mass_error())),
                "packing_min": low, "packing_max": high}

    def save_state(self) -> dict[str, Any]:
        return {"packing_outputs": {"error_max": self.error_max, "low": self.extremes[0],
                                    "high": self.extremes[1]}}

    def restore_state(self, state: dict[str, Any]) -> None:
        saved = state.get("packing_outputs")
        if saved is not None:
            self.error_max = float(saved["error_max"])
            self.extremes = [float(saved["low"]), float(saved["high"])]
