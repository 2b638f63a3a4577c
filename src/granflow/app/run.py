"""Runs a configured scenario into a run directory (its layout: docs/user_guide.md).

The runner builds the problem by its kind (``scenarios/registry.py``) and attaches the
files to its time loop on schedules (each file owns its writer and its reader:
``io/diagnostics.py``, ``io/profiles.py``, ``io/fields.py``, ``io/frames.py``,
``io/checkpoint.py``). What goes into them beside the loop's own measures it gathers by
walking the simulation's named callbacks (``simulation.callbacks``,
``simulation/outputs.py``): each part of the problem declares its diagnostics columns,
profiles, cell data, animation frames and summary members, and the runner never asks what
the problem is. It writes ``summary.json`` at the start (``running``) and at the end, also
when the run fails or is interrupted: whatever was written before stays readable, and
``granflow resume`` continues from the checkpoint. Figures are drawn last, from the files,
by the problem kind's figures.
"""

from __future__ import annotations

import contextlib
import math
import signal
import threading
import traceback
from collections.abc import Iterator
from typing import Any

import ngsolve as ngs

from granflow.config import Config
from granflow.diagnostics.flow_fields import FlowSnapshot
from granflow.diagnostics.state import state_measures
from granflow.fem.linalg import solver_in_use
from granflow.fem.sampling import cell_means
from granflow.io import profiles
from granflow.io.checkpoint import write_checkpoint
from granflow.io.diagnostics import COLUMNS as DIAGNOSTIC_COLUMNS
from granflow.io.diagnostics import DiagnosticsLog
from granflow.io.fields import FieldSnapshots
from granflow.io.frames import INTERVAL_S as ANIMATION_INTERVAL_S
from granflow.io.frames import AnimationFrames
from granflow.io.report import display_path
from granflow.io.run_dir import SUMMARY_LIST_LIMIT, RunDir, RunDirError
from granflow.io.run_state import SimulationState
from granflow.scenarios.registry import Problem, build_problem, draw_figures
from granflow.simulation.callbacks import (
    AtTimes,
    EveryNSteps,
    ProgressBar,
    TimeInterval,
    add_callback,
)
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import RunResult, Simulation
from granflow.state.spec import (
    TIME,
    Dims,
    Share,
    check_share,
    list_of,
    may_lack,
    number,
    or_none,
)

__all__ = ["ANIMATION_INTERVAL_S", "DIAGNOSTIC_COLUMNS", "Problem", "build_problem",
           "run_simulation"]

EVENTS = ("remesh", "deposition")     # marked in the figures (summary.json NAME_times_s)
# the outputs' share of a checkpoint (``_Run.checkpoint``): the runner's and its files'
OUTPUTS_SHARE: Share = {
    "volume0": may_lack(or_none(number(0.0, above=True))),
    **{f"{name}_times": may_lack(list_of(TIME, most=SUMMARY_LIST_LIMIT)) for name in EVENTS},
    "pending_times": may_lack(list_of(TIME)), "animation_next": may_lack(or_none(TIME)),
    **DiagnosticsLog.share, **FieldSnapshots.share, **AnimationFrames.share}


def write_profiles(run_dir: RunDir, problem: Problem, t: float, final: bool = False) -> None:
    """The profiles its callbacks declare at time ``t`` (or of the last state) into
    profiles/."""
    for kind, (columns, rows) in problem.simulation.callbacks.profiles(t).items():
        profiles.write_profile(run_dir, kind, t, columns, rows, final=final)


def checked_state(state: SimulationState, problem: Problem | None) -> SimulationState:
    """``state`` with every member of its three shares checked against what its parts
    declare (``state/spec.py``) and only those kept: the one check of a
    checkpoint's content before any part reads it; ``StateError`` (one line) names the
    first member that is not what its part declared. Without a problem (its build failed:
    the run fails, nothing reads the problem's share) that share is left as it is."""
    dims: Dims = {}
    loop = check_share(state.loop, Simulation.share, "loop", dims)
    scenario = (state.scenario if problem is None else
                check_share(state.scenario, problem.share(), "scenario", dims))
    outputs = check_share(state.outputs, OUTPUTS_SHARE, "outputs", dims)
    return SimulationState(loop=loop, scenario=scenario, outputs=outputs,
                           version=state.version)


def run_simulation(config: Config, run_dir: RunDir, progress: bool = True,
                   resume: SimulationState | None = None,
                   problem: Problem | None = None) -> dict[str, Any]:
    """Run ``config`` into ``run_dir`` (or continue ``resume``, a checkpointed state of it,
    checked and restored into ``problem`` if the caller did so already, as
    ``resuming.resume_run`` does); return the summary, also written as summary.json.

    The caller holds the folder's lock (``run_dir.lock()``) for the whole run: it is taken
    once, by whoever creates or reopens the folder (``granflow.run``, ``granflow resume``, a
    sweep). summary.json says ``running`` from the start; SIGINT and SIGTERM end the run
    after the current step with ``interrupted`` and a checkpoint; a failing run checkpoints
    its last accepted state. Errors while the problem is built are a ``failed`` summary
    too, never an escaping exception.
    """
    if not run_dir.locked:
        raise RunDirError(f"run directory '{run_dir.root}' must be locked by its writer "
                          "(with run_dir.lock(): ...) before a run starts")
    started = "resumed" if resume else "started"
    for stale in [*run_dir.written(f"{profiles.FOLDER}/*_{profiles.FINAL}.csv"),
                  *run_dir.written(f"{profiles.FOLDER}/final_error.txt")]:
        if not stale.is_dir():
            stale.unlink(missing_ok=True)   # of an earlier session
    run_dir.write_json("summary.json", _summary_head(
        config, "running", f"{started} at t = {resume.t if resume else 0.0:.6g} s"))
    try:
        if problem is None:
            problem = build_problem(config)
            if resume is not None:
                resume = checked_state(resume, problem)
                problem.restore_state(resume.scenario)
                problem.simulation.restore_state(resume.loop)
    except Exception as exc:  # a failure to build is a result, with the traceback kept
        return _failed(config, run_dir, exc, "building the problem")
    return _Run(config, run_dir, problem, progress, resume).execute()


def _summary_head(config: Config, status: str, message: str) -> dict[str, Any]:
    return {"scenario": config.scenario, "status": status, "message": message,
            "linear_solver": solver_in_use(config.numerics.linear_solver)}


def _failed(config: Config, run_dir: RunDir, exc: Exception, when: str) -> dict[str, Any]:
    run_dir.write_text("traceback.txt", traceback.format_exc())
    summary = _summary_head(config, "failed", f"{type(exc).__name__} while {when}: {exc}")
    run_dir.write_json("summary.json", summary)
    return summary


class RunRecord(Outputs):
    """The run's own part of summary.json, declared as the loop's callback ``run`` like
    every other part's members: its counts and events (after each accepted step it notes
    the remeshes and the depositions, which the figures mark: each changes the kinetic
    energy at once), the output times after the stop, the last state's profiles, the
    volume's conservation and the mesh's size. Its state is in the outputs' share of the
    checkpoint (``OUTPUTS_SHARE``). It notes the first ``SUMMARY_LIST_LIMIT`` events of
    each kind (what summary.json's reader reads; the remeshes' count is the remesher's)."""

    def __init__(self, problem: Problem, saved: dict[str, Any] | None, resumed: bool,
                 at_times: AtTimes) -> None:
        self.problem, self.resumed, self.at_times = problem, resumed, at_times
        solver = problem.solver
        self.volume0 = (saved or {}).get("volume0") or state_measures(
            problem.mesh, solver.velocity, solver.density, coords=solver.coordinates)["volume"]
        self.events = {name: [float(t) for t in (saved or {}).get(f"{name}_times", [])
                              if isinstance(t, int | float)] for name in EVENTS}
        self.seen = _event_counts(problem)
        self.final: float | None = None      # the time of profiles/*_final.csv, once written

    def __call__(self, sim: Simulation) -> None:
        counts = _event_counts(self.problem)
        for name, count in counts.items():   # the first SUMMARY_LIST_LIMIT of each kind
            if count > self.seen[name] and len(self.events[name]) < SUMMARY_LIST_LIMIT:
                # a remesh comes before the step's move, a landing on the bed ends it
                self.events[name].append(sim.t - sim.dt if name == "remesh" else sim.t)
        self.seen = counts

    def outputs_state(self) -> dict[str, Any]:
        """Its members of the outputs' share of the checkpoint."""
        return {"volume0": self.volume0,
                **{f"{k}_times": list(v) for k, v in self.events.items()}}

    def summary(self, result: RunResult) -> dict[str, Any]:
        problem, solver = self.problem, self.problem.solver
        volume = state_measures(problem.mesh, solver.velocity, solver.density,
                                coords=solver.coordinates)["volume"]
        # output times after the mass came to rest are never reached: nothing is written for
        # them, the state at rest (profiles/*_final.csv, the last VTU) stands for them
        at_rest = list(self.at_times.pending) if result.status == "stopped" else []
        return {
            "t_final": result.t_final,
            "steps": result.steps,
            "rejected_steps": result.rejected_steps,
            "rejections": result.rejections,
            "outputs_at_rest": at_rest,   # output times after the stop: the rest state's
            "remesh_times_s": self.events["remesh"],          # the mesh replaced
            "deposition_times_s": self.events["deposition"],  # surface edges onto the bed
            "final_profiles_t": self.final,   # profiles/*_final.csv: the last accepted state
            "skipped_remeshes": result.skipped_remeshes,
            "remesh_failures": result.remesh_failures,    # remeshes that raised, by error
            "history_restarts": result.history_restarts,   # surface tension on/off
            "remeshed_moves": result.remeshed_moves,   # folds foreseen, remeshed before
            "nonlinear_iterations": result.nonlinear_iterations,
            "linear_solves": result.linear_solves,
            "wall_time_s": result.wall_time_s,
            "stop_time_s": None,       # a kind that stops at rest or has a runout says
            "runout_m": None,
            "volume_relative_error": abs(volume - self.volume0) / self.volume0,
            "n_triangles": problem.mesh.ne,
            "n_dofs": solver.space.ndof,
            "resumed": self.resumed,
            **solver.linear_work(),     # an iterative solve's steps (fem/fieldsplit.py)
        }


class _Run:
    """One run's files wired to its loop: each is a named callback on a schedule, after
    the problem's parts, and gives its share of the checkpoint (``save_state``); what they
    hold of the problem is what those parts declare."""

    def __init__(self, config: Config, run_dir: RunDir, problem: Problem, progress: bool,
                 resume: SimulationState | None) -> None:
        self.config, self.run_dir, self.problem = config, run_dir, problem
        self.resumed = resume is not None
        sim = self.sim = problem.simulation
        saved = resume.outputs if resume is not None else None
        callbacks = sim.callbacks
        self.diagnostics = DiagnosticsLog(run_dir, saved, columns=callbacks.columns())
        self.fields = FieldSnapshots(run_dir, FlowSnapshot(problem), saved,
                                     cell_data=callbacks.fields)
        self.bar = ProgressBar(config.time.t_end, enabled=progress, initial=sim.t)
        self.at_times = AtTimes(config.time.output_times, self._outputs_at)
        if resume is not None:   # those still ahead (the configuration may have changed them)
            self.at_times.pending = [x for x in config.time.output_times
                                     if x > sim.t + 1e-9 * max(1.0, x)]
        source = callbacks.frame_source()
        self.frames = (AnimationFrames(run_dir, source.frame, saved)
                       if source is not None else None)
        self.animation = (TimeInterval(ANIMATION_INTERVAL_S, self.frames.write)
                          if self.frames is not None else None)
        if self.animation is not None:
            self.animation.next = (saved or {}).get("animation_next", self.animation.next)
        self.record = RunRecord(problem, saved, self.resumed, self.at_times)
        # the files, after the problem's parts (they read the advanced state)
        add_callback(sim, self._record, "diagnostics")
        add_callback(sim, self.record, "run", first=True)   # the others refine its members
        add_callback(sim, self.bar, "progress")
        add_callback(sim, self.at_times, "output_times")
        add_callback(sim, lambda s: self.fields.write(s.t), "fields",
                     schedule=EveryNSteps(config.output.vtk_every))
        if self.animation is not None:
            add_callback(sim, self.animation, "animation")
        add_callback(sim, self.checkpoint, "checkpoint",   # last: of the step's whole state
                     schedule=EveryNSteps(config.output.checkpoint_every))

    # --- callbacks ----------------------------------------------------------------------
    def _record(self, s: Simulation) -> None:
        """One diagnostics row per accepted step."""
        problem = self.problem
        report, estimate = s.last_report, s.last_estimate
        row = {"t": s.t, "dt": s.dt, "iterations": report.iterations,
               "linear_solves": report.linear_solves,
               "local_error": estimate.error if estimate is not None else math.nan}
        speed = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))  # once per step
        row |= s.callbacks.diagnostics(s, speed[0])
        row |= state_measures(problem.mesh, problem.solver.velocity, problem.solver.density,
                              speed, problem.solver.coordinates)
        self.diagnostics.write(row)
        s.callbacks.record(row)

    def _outputs_at(self, s: Simulation, t: float) -> None:
        write_profiles(self.run_dir, self.problem, t)
        self.fields.write(t)

    def checkpoint(self, s: Simulation) -> None:
        outputs: dict[str, Any] = {**self.record.outputs_state(),
                                   "pending_times": list(self.at_times.pending),
                                   "animation_next": (self.animation.next
                                                      if self.animation is not None else None)}
        for output in (self.diagnostics, self.fields, self.frames):
            if output is not None:
                outputs |= output.save_state()
        write_checkpoint(self.run_dir, SimulationState(
            loop=s.save_state(), scenario=self.problem.save_state(), outputs=outputs))
        fresh_factorisations(self.problem)

    # --- the run --------------------------------------------------------------------------
    def execute(self) -> dict[str, Any]:
        sim, run_dir = self.sim, self.run_dir
        if not self.resumed:
            self.fields.write(0.0)
            if self.frames is not None:
                self.frames.write(sim)      # the animation starts from the column at rest
        crashed: Exception | None = None
        result: RunResult | None = None
        try:
            with _interrupts_to(sim):
                result = sim.run()
            # the last accepted state: `granflow resume` continues an interrupted or failed
            # run from it, and extends a finished one to a later time.t_end
            self.checkpoint(sim)
            if result.status in ("interrupted", "failed"):
                result.message += f"; continue with `granflow resume {run_dir.root}`"
        except Exception as exc:  # keep what was written; report instead of crashing
            crashed = exc
            result = RunResult("failed", f"{type(exc).__name__} at t = {sim.t:.6g} s, step "
                               f"{sim.step}: {exc}", sim.t, sim.step, sim.rejected_steps,
                               sim.nonlinear_iterations, sim.linear_solves, sim.wall_time(),
                               dict(sim.rejections))
            run_dir.write_text("traceback.txt", traceback.format_exc())
        finally:
            stopped = result is not None and result.status == "stopped"
            rest = _rest_since(sim) if stopped else None
            self.bar.close("" if not stopped else "at rest" if rest is None
                           else f"at rest from t = {rest:.3f} s", complete=stopped)
            self.diagnostics.close()
        self.record.final = self._write_final_state() if crashed is None else None
        summary = (_summary_head(self.config, result.status, result.message)
                   | sim.callbacks.summary(result))
        run_dir.write_json("summary.json", summary)
        self.bar.say(f"drawing the figures into {display_path(run_dir.path('plots'))}")
        try:
            draw_figures(run_dir, self.config)
        except Exception as exc:  # a figure must never turn a finished run into a failure
            run_dir.write_text("plots/error.txt", f"{type(exc).__name__}: {exc}\n")
        return summary

    def _write_final_state(self) -> float | None:
        """The last accepted state as profiles/*_final.csv and a last VTU snapshot: the
        deposit of a run that stopped, where a failed run stood. Returns its time, or None
        if it could not be written (the reason in profiles/final_error.txt)."""
        t = self.sim.t
        try:
            write_profiles(self.run_dir, self.problem, t, final=True)
            self.fields.write_last(t)
        except Exception as exc:  # an output must never turn a finished run into a failure
            self.run_dir.write_text(f"{profiles.FOLDER}/final_error.txt",
                                    f"{type(exc).__name__}: {exc}\n")
            return None
        return t


def _event_counts(problem: Problem) -> dict[str, int]:
    """How many remeshes and depositions (free-surface edges relabelled as bed, paper
    Figure 2) the problem has had so far (none for a fixed mesh)."""
    remesher, mover = getattr(problem, "remesher", None), getattr(problem, "mover", None)
    return {"remesh": int(getattr(remesher, "remeshes", 0)),
            "deposition": int(getattr(mover, "relabelled_segments", 0))}


def _rest_since(sim: Simulation) -> float | None:
    """When the mass came to rest, by the stop criterion that ended the run."""
    return next((float(c.rest_since) for c in sim.stop_criteria
                 if getattr(c, "rest_since", None) is not None), None)


def fresh_factorisations(problem: Problem) -> None:
    """After a checkpoint the sparse LUs start afresh, as they do in a run resumed from it:
    PARDISO's analysis (pivot order, scaling) reads the matrix's values, so reusing one made
    on an earlier step's matrix gives round-off differences that the nonlinear iteration
    counts then amplify (a resumed run would not repeat the run that wrote the checkpoint).
    The flow's couplings solve systems of their own (a nonlocal law's fluidity): theirs too."""
    problem.solver.reset_factorisations()
    velocity = getattr(problem.simulation.mesh_motion, "velocity_solver", None)
    if velocity is not None:
        velocity.forget_factorisation()


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
