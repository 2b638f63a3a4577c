"""Runs a configured scenario into a run directory (DESIGN.md, "A run directory contains").

The runner wires observers (diagnostics rows, profiles at output times, VTU snapshots, a
progress bar) around a scenario's time loop and writes ``summary.json`` at the end, also
when the run fails: whatever was written before stays readable.
"""

from __future__ import annotations

import math
import traceback
from typing import Any, Protocol

import ngsolve as ngs
import numpy as np

from granflow.config import Config
from granflow.diagnostics.state import FLOWING_SPEED, state_measures
from granflow.fem.flow import FlowSolver
from granflow.fem.sampling import cell_means, triangles, vertex_samples
from granflow.io.run_dir import RunDir
from granflow.io.vtk import VtkSeries
from granflow.simulation.callbacks import AtTimes, EveryNSteps, ProgressBar, TimeInterval
from granflow.simulation.simulation import RunResult, Simulation

DIAGNOSTIC_COLUMNS = ["t", "dt", "iterations", "front_x", "wall_height", "volume",
                      "kinetic_energy", "max_speed", "flowing_fraction", "linear_solves",
                      "local_error", "tension_on", "tension_x"]
ANIMATION_INTERVAL_S = 0.02


class Problem(Protocol):
    """What a scenario builder hands to the runner."""

    mesh: ngs.Mesh
    solver: FlowSolver
    simulation: Simulation

    def shape_measures(self, cell_speed: np.ndarray) -> dict[str, float]: ...
    def record(self, row: dict[str, float]) -> None: ...
    def write_profiles(self, run_dir: RunDir, t: float) -> None: ...
    def summary(self, result: RunResult) -> dict[str, Any]: ...
    def plot(self, run_dir: RunDir) -> None: ...


def build_problem(config: Config) -> Problem:
    """Scenario builder for ``geometry.kind``."""
    if config.geometry.kind == "periodic-layer":
        from granflow.scenarios.plug_flow import build_plug_flow

        return build_plug_flow(config)
    from granflow.scenarios.column import build_column

    return build_column(config)


def write_fields(series: VtkSeries, problem: Problem, t: float) -> None:
    """Velocity, pressure, |Du|, effective viscosity and the flowing flag at the vertices."""
    solver, mesh = problem.solver, problem.mesh
    speed, _ = cell_means(mesh, ngs.Norm(solver.velocity))
    series.write(
        t, mesh.ngmesh.Coordinates().copy(), triangles(mesh),
        point_data={
            "velocity": vertex_samples(mesh, solver.velocity),
            "pressure": vertex_samples(mesh, solver.pressure),
        },
        cell_data={"flowing": (speed > FLOWING_SPEED).astype(float), "speed": speed,
                   "strain_rate_norm": cell_means(mesh, solver.strain_rate_norm())[0],
                   "effective_viscosity": cell_means(mesh, solver.effective_viscosity())[0]})


def run_simulation(config: Config, run_dir: RunDir, progress: bool = True) -> dict[str, Any]:
    """Run ``config`` into ``run_dir``; return the summary (also written as summary.json)."""
    problem = build_problem(config)
    sim = problem.simulation
    volume0 = state_measures(problem.mesh, problem.solver.velocity,
                             problem.solver.density)["volume"]
    log = run_dir.csv_log("diagnostics.csv", DIAGNOSTIC_COLUMNS)
    series = VtkSeries(run_dir.path("fields"))
    bar = ProgressBar(config.time.t_end, enabled=progress)

    def record(s: Simulation) -> None:
        report, estimate = s.last_report, s.last_estimate
        row = {"t": s.t, "dt": s.dt, "iterations": report.iterations,
               "linear_solves": report.linear_solves,
               "local_error": estimate.error if estimate is not None else math.nan}
        speed = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))  # once per step
        row |= problem.shape_measures(speed[0])
        row |= state_measures(problem.mesh, problem.solver.velocity, problem.solver.density,
                              speed)
        log.write([row.get(c, math.nan) for c in DIAGNOSTIC_COLUMNS])
        problem.record(row)

    def outputs(s: Simulation, t: float) -> None:
        problem.write_profiles(run_dir, t)
        write_fields(series, problem, t)

    at_times = AtTimes(config.time.output_times, outputs)
    observers = [record, bar, at_times,
                 EveryNSteps(config.output.vtk_every, lambda s: write_fields(series, problem, s.t))]
    snapshot = getattr(problem, "snapshot", None)
    if snapshot is not None:
        observers.append(TimeInterval(ANIMATION_INTERVAL_S, snapshot))
    sim.observers = [*sim.observers, *observers]
    write_fields(series, problem, 0.0)
    try:
        result = sim.run()
    except Exception as exc:  # keep what was written; report instead of crashing
        result = RunResult("failed", f"{type(exc).__name__} at t = {sim.t:.6g} s, step "
                           f"{sim.step}: {exc}", sim.t, sim.step, sim.rejected_steps,
                           sim.nonlinear_iterations, sim.linear_solves,
                           sim.unconverged_steps, math.nan, dict(sim.rejections))
        run_dir.write_text("traceback.txt", traceback.format_exc())
    finally:
        bar.close()
        log.close()
    at_rest = at_times.flush(sim) if result.status == "stopped" else []
    solver = problem.solver
    volume = state_measures(problem.mesh, solver.velocity, solver.density)["volume"]
    summary: dict[str, Any] = {
        "scenario": config.scenario,
        "status": result.status,
        "message": result.message,
        "t_final": result.t_final,
        "steps": result.steps,
        "rejected_steps": result.rejected_steps,
        "rejections": result.rejections,
        "outputs_at_rest": at_rest,   # output times written from the final (rest) state
        "unconverged_steps": result.unconverged_steps,
        "nonlinear_iterations": result.nonlinear_iterations,
        "linear_solves": result.linear_solves,
        "wall_time_s": result.wall_time_s,
        "stop_time_s": None,
        "runout_m": None,
        "volume_relative_error": abs(volume - volume0) / volume0,
        "n_triangles": problem.mesh.ne,
        "n_dofs": solver.space.ndof,
    }
    summary |= problem.summary(result)
    run_dir.write_json("summary.json", summary)
    try:
        problem.plot(run_dir)
    except Exception as exc:  # a figure must never turn a finished run into a failure
        run_dir.write_text("plots/error.txt", f"{type(exc).__name__}: {exc}\n")
    return summary
