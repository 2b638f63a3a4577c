"""The granular fluidity of a nonlocal law (``physics/nonlocal_fluidity.py``) in a problem:
the coupling of the field to the flow with its boundary conditions (``fem/fluidity.py``:
solved with the flow, carried through a remesh, kept in the checkpoint's flow history), and
its outputs.

Boundary conditions: g = 0 on a rough no-slip base (the periodic layer's bed); zero flux at
the free surface and the walls; on a column's Coulomb bed ``boundary.bed_fluidity`` chooses
(zero flux by default: the material slides and shears there, docs/model.md). With A = 0 the
equation has no derivative in space and takes no condition.

``fluidity_growth_rate`` runs a problem and measures how fast its fluidity grows or decays: the
stopping height's test and benchmark (a small g in a layer at rest decays below h_stop and
grows above it).

Its outputs (``simulation/outputs.py``): the diagnostics columns ``fluidity_max`` and
``fluidity_mean`` (over the mass, area- or in r-z volume-weighted, 1/s) and the cell data
``fluidity`` of the VTU snapshots (the mean of g over each triangle).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import ngsolve as ngs
import numpy as np

from granflow.config import Config
from granflow.fem.flow import FlowSolver
from granflow.fem.fluidity import FluidityCoupling, FluidityField, FluiditySpec
from granflow.physics.nonlocal_fluidity import NonlocalFluidity
from granflow.scenarios.materials import RunMaterials, nonlocal_law
from granflow.simulation.callbacks import add_callback
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import Simulation


def fluidity_specs(config: Config, materials: RunMaterials, *, rough: str = "",
                   initial: Callable[[NonlocalFluidity, Config], Any] | None = None,
                   ) -> tuple[FluiditySpec, ...]:
    """The fluidity of the run's nonlocal ``materials`` (none without them); g = 0 on the
    boundaries ``rough`` (a "|"-joined list of labels) when A > 0; ``initial(law,
    config)``: g at t = 0 (None: 0)."""
    materials_ = materials.nonlocal_
    if not materials_:
        return ()
    laws = tuple(nonlocal_law(mat, config.numerics.eps) for mat in materials_)
    dirichlet = rough if any(law.amplitude > 0 for law in laws) else ""
    start = initial(laws[0], config) if initial is not None else None
    return (FluiditySpec(laws, dirichlet, config.numerics.fluidity_coupling == "iterated",
                         start),)


def fluidity_of(solver: FlowSolver) -> FluidityField | None:
    """The fluidity field of a solver, None without a nonlocal law."""
    coupling = solver.coupling(FluidityCoupling)
    return coupling.field if coupling is not None else None


class Host(Protocol):
    """Where the current flow solver lives (a collapse's remesh replaces it)."""

    solver: FlowSolver


@dataclass
class FluidityOutputs(Outputs):
    """The fluidity's columns and cell data (module docstring)."""

    columns = ("fluidity_max", "fluidity_mean")

    current: Host

    @classmethod
    def of(cls, current: Host) -> FluidityOutputs | None:
        """The outputs of the fluidity of ``current``'s solver (None without one)."""
        return cls(current) if fluidity_of(current.solver) is not None else None

    @property
    def field(self) -> FluidityField:
        field = fluidity_of(self.current.solver)
        assert field is not None
        return field

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        solver, field = self.current.solver, self.field
        mean = solver.coordinates.integrate(field.previous, solver.mesh) / solver.volume()
        return {"fluidity_max": float(np.max(field.vertex_values(), initial=0.0)),
                "fluidity_mean": float(mean)}

    def fields(self) -> dict[str, np.ndarray]:
        return {"fluidity": self.field.cell_means()}


def fluidity_growth_rate(solver: FlowSolver, simulation: Any, mesh: ngs.Mesh,
                         after: float) -> float:
    """Run ``simulation`` and return the log-slope (1/s) of the fluidity's L2 norm over the
    accepted steps later than ``after`` (a least-squares line through log ||g||)."""
    field = fluidity_of(solver)
    if field is None:
        raise ValueError("fluidity_growth_rate needs a nonlocal law "
                         "(material.rheology = 'nonlocal')")
    times, norms = [], []

    def record(sim: Any) -> None:
        times.append(sim.t)
        norms.append(math.sqrt(ngs.Integrate(field.previous**2, mesh)))

    add_callback(simulation, record, "fluidity growth")
    simulation.run()
    t, n = np.array(times), np.array(norms)
    late = t > after
    return float(np.polyfit(t[late], np.log(n[late]), 1)[0])
