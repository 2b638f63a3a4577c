"""Runs a configured scenario into a run directory (its layout: docs/user_guide.md).

The runner wires observers (diagnostics rows, profiles at output times, VTU snapshots, a
progress bar, checkpoints) around a scenario's time loop, writes ``summary.json`` at the
start (``running``) and at the end, also when the run fails or is interrupted: whatever was
written before stays readable, and ``granflow resume`` continues from the checkpoint.
"""

from __future__ import annotations

import contextlib
import math
import signal
import threading
import traceback
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Protocol

import ngsolve as ngs
import numpy as np

from granflow.config import Config
from granflow.diagnostics.state import FLOWING_SPEED, state_measures
from granflow.fem.flow import FlowSolver
from granflow.fem.linalg import solver_in_use
from granflow.fem.sampling import cell_means, triangles, vertex_samples
from granflow.io.checkpoint import write_checkpoint
from granflow.io.frames import write_frame
from granflow.io.run_dir import RunDir, atomic_write_bytes
from granflow.io.run_state import SimulationState
from granflow.io.vtk import VtkSeries
from granflow.simulation.callbacks import AtTimes, EveryNSteps, ProgressBar, TimeInterval
from granflow.simulation.simulation import RunResult, Simulation

DIAGNOSTIC_COLUMNS = ["t", "dt", "iterations", "front_x", "wall_height", "volume",
                      "kinetic_energy", "max_speed", "flowing_fraction", "linear_solves",
                      "local_error", "tension_on", "tension_x", "area_correction",
                      "remesh_area_change"]
ANIMATION_INTERVAL_S = 0.02


class Problem(Protocol):
    """What a scenario builder hands to the runner."""

    mesh: ngs.Mesh
    solver: FlowSolver
    simulation: Simulation

    def shape_measures(self, cell_speed: np.ndarray) -> dict[str, float]: ...
    def record(self, row: dict[str, float]) -> None: ...
    def write_profiles(self, run_dir: RunDir, t: float, label: str | None = None) -> None: ...
    def summary(self, result: RunResult) -> dict[str, Any]: ...
    def plot(self, run_dir: RunDir) -> None: ...
    def save_state(self) -> dict[str, Any]: ...
    def restore_state(self, state: dict[str, Any]) -> None: ...


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


def run_simulation(config: Config, run_dir: RunDir, progress: bool = True,
                   resume: SimulationState | None = None) -> dict[str, Any]:
    """Run ``config`` into ``run_dir`` (or continue ``resume``, a checkpointed state of it);
    return the summary, also written as summary.json.

    The folder is locked for the whole run. summary.json says ``running`` from the start;
    SIGINT and SIGTERM end the run after the current step with ``interrupted`` and a
    checkpoint; a failing run checkpoints its last accepted state. Errors while the problem
    is built are a ``failed`` summary too, never an escaping exception.
    """
    with run_dir.lock():
        return _run_locked(config, run_dir, progress, resume)


def _summary_head(config: Config, status: str, message: str) -> dict[str, Any]:
    return {"scenario": config.scenario, "status": status, "message": message,
            "linear_solver": solver_in_use(config.numerics.linear_solver)}


def _failed(config: Config, run_dir: RunDir, exc: Exception, when: str) -> dict[str, Any]:
    run_dir.write_text("traceback.txt", traceback.format_exc())
    summary = _summary_head(config, "failed", f"{type(exc).__name__} while {when}: {exc}")
    run_dir.write_json("summary.json", summary)
    return summary


def _run_locked(config: Config, run_dir: RunDir, progress: bool,
                resume: SimulationState | None) -> dict[str, Any]:
    started = "resumed" if resume else "started"
    for stale in [*run_dir.path("profiles").glob("*_final.csv"),   # of an earlier session
                  run_dir.path("profiles/final_error.txt")]:
        stale.unlink(missing_ok=True)
    run_dir.write_json("summary.json", _summary_head(
        config, "running", f"{started} at t = {resume.t if resume else 0.0:.6g} s"))
    try:
        problem = build_problem(config)
        if resume is not None:
            problem.restore_state(resume.scenario)
            problem.simulation.restore_state(resume.loop)
    except Exception as exc:  # a failure to build is a result, with the traceback kept
        return _failed(config, run_dir, exc, "building the problem")
    sim = problem.simulation
    outputs = resume.outputs if resume is not None else {}
    volume0 = outputs.get("volume0") or state_measures(
        problem.mesh, problem.solver.velocity, problem.solver.density)["volume"]
    if resume is not None:
        _truncate_rows(run_dir.path("diagnostics.csv"), outputs["diagnostic_rows"])
    log = run_dir.csv_log("diagnostics.csv", DIAGNOSTIC_COLUMNS, resume=resume is not None)
    rows = outputs.get("diagnostic_rows", 0)
    series = VtkSeries(run_dir.path("fields"))
    series.entries = list(outputs.get("vtk_entries", []))
    bar = ProgressBar(config.time.t_end, enabled=progress, initial=sim.t)

    def record(s: Simulation) -> None:
        nonlocal rows
        report, estimate = s.last_report, s.last_estimate
        row = {"t": s.t, "dt": s.dt, "iterations": report.iterations,
               "linear_solves": report.linear_solves,
               "local_error": estimate.error if estimate is not None else math.nan}
        speed = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))  # once per step
        row |= problem.shape_measures(speed[0])
        row |= state_measures(problem.mesh, problem.solver.velocity, problem.solver.density,
                              speed)
        log.write([row.get(c, math.nan) for c in DIAGNOSTIC_COLUMNS])
        rows += 1
        problem.record(row)

    def outputs_at(s: Simulation, t: float) -> None:
        problem.write_profiles(run_dir, t)
        write_fields(series, problem, t)

    at_times = AtTimes(config.time.output_times, outputs_at)
    if resume is not None:   # those still ahead (the configuration may have changed them)
        at_times.pending = [x for x in config.time.output_times
                            if x > sim.t + 1e-9 * max(1.0, x)]
    observers = [record, bar, at_times,
                 EveryNSteps(config.output.vtk_every, lambda s: write_fields(series, problem, s.t))]
    frame = getattr(problem, "frame", None)
    frames_written = outputs.get("frames_written", 0)

    def write_animation_frame(s: Simulation) -> None:
        nonlocal frames_written
        assert frame is not None
        write_frame(run_dir, frames_written, frame(s))
        frames_written += 1

    animation = (TimeInterval(ANIMATION_INTERVAL_S, write_animation_frame)
                 if frame is not None else None)
    if animation is not None:
        animation.next = outputs.get("animation_next", animation.next)
        observers.append(animation)
    sim.observers = [*sim.observers, *observers]

    def checkpoint(s: Simulation) -> None:
        write_checkpoint(run_dir, SimulationState(
            loop=s.save_state(), scenario=problem.save_state(),
            outputs={"volume0": volume0, "diagnostic_rows": rows,
                     "pending_times": list(at_times.pending),
                     "vtk_entries": list(series.entries),
                     "animation_next": animation.next if animation is not None else None,
                     "frames_written": frames_written}))

    sim.checkpoint, sim.checkpoint_every = checkpoint, config.output.checkpoint_every
    if resume is None:
        write_fields(series, problem, 0.0)
        if animation is not None:
            write_animation_frame(sim)      # the animation starts from the column at rest
    crashed: Exception | None = None
    result: RunResult | None = None
    try:
        with _interrupts_to(sim):
            result = sim.run()
        if result.status in ("interrupted", "failed"):
            checkpoint(sim)        # the last accepted state: `granflow resume` goes on
            result.message += f"; continue with `granflow resume {run_dir.root}`"
    except Exception as exc:  # keep what was written; report instead of crashing
        crashed = exc
        result = RunResult("failed", f"{type(exc).__name__} at t = {sim.t:.6g} s, step "
                           f"{sim.step}: {exc}", sim.t, sim.step, sim.rejected_steps,
                           sim.nonlinear_iterations, sim.linear_solves,
                           sim.unconverged_steps, sim.wall_time(), dict(sim.rejections))
        run_dir.write_text("traceback.txt", traceback.format_exc())
    finally:
        bar.close("at rest" if result is not None and result.status == "stopped" else "")
        log.close()
    final = _write_final_state(run_dir, problem, series, sim) if crashed is None else None
    at_rest = at_times.flush(sim) if result.status == "stopped" else []
    solver = problem.solver
    volume = state_measures(problem.mesh, solver.velocity, solver.density)["volume"]
    summary: dict[str, Any] = _summary_head(config, result.status, result.message) | {
        "t_final": result.t_final,
        "steps": result.steps,
        "rejected_steps": result.rejected_steps,
        "rejections": result.rejections,
        "outputs_at_rest": at_rest,   # output times written from the final (rest) state
        "final_profiles_t": final,    # profiles/*_final.csv: the last accepted state
        "unconverged_steps": result.unconverged_steps,
        "nonlinear_iterations": result.nonlinear_iterations,
        "linear_solves": result.linear_solves,
        "wall_time_s": result.wall_time_s,
        "stop_time_s": None,
        "runout_m": None,
        "volume_relative_error": abs(volume - volume0) / volume0,
        "n_triangles": problem.mesh.ne,
        "n_dofs": solver.space.ndof,
        "resumed": resume is not None,
    }
    summary |= problem.summary(result)
    run_dir.write_json("summary.json", summary)
    bar.say(f"drawing the figures into {run_dir.path('plots')}")
    try:
        problem.plot(run_dir)
    except Exception as exc:  # a figure must never turn a finished run into a failure
        run_dir.write_text("plots/error.txt", f"{type(exc).__name__}: {exc}\n")
    return summary


def _write_final_state(run_dir: RunDir, problem: Problem, series: VtkSeries,
                       sim: Simulation) -> float | None:
    """The last accepted state as profiles/*_final.csv and a last VTU snapshot: the deposit
    of a run that stopped, where a failed run stood. Returns its time, or None if it could
    not be written (the reason in profiles/final_error.txt; the run's result stands)."""
    try:
        problem.write_profiles(run_dir, sim.t, "final")
        if not series.entries or abs(series.entries[-1][0] - sim.t) > 1e-12:
            write_fields(series, problem, sim.t)
    except Exception as exc:  # an output must never turn a finished run into a failure
        run_dir.write_text("profiles/final_error.txt", f"{type(exc).__name__}: {exc}\n")
        return None
    return sim.t


@contextlib.contextmanager
def _interrupts_to(sim: Simulation) -> Iterator[None]:
    """SIGINT and SIGTERM ask the loop to stop after the current step (main thread only:
    elsewhere, e.g. in a Dask worker, signals stay with their owner)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum: int, frame: object) -> None:
        sim.interrupt = f"{signal.Signals(signum).name} received"

    previous = {sig: signal.signal(sig, handler) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, old in previous.items():
            signal.signal(sig, old)


def _truncate_rows(path: Path, rows: int) -> None:
    """Keep the header and the first ``rows`` rows of a CSV log (those the checkpoint has
    seen): rows written after it by the killed run are replayed by the resumed one."""
    if not path.is_file():
        return
    lines = path.read_text(encoding="utf-8").splitlines(keepends=True)
    atomic_write_bytes(path, "".join(lines[:rows + 1]).encode("utf-8"))
