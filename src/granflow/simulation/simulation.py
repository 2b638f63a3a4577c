"""The time loop: mesh velocity -> move -> nonlinear solve -> accept/reject (section 3.3).

It owns the stop criteria and says why it stopped; after each accepted step (and its
stop tests) it runs its named callbacks (``simulation.callbacks[name]``,
``simulation/callbacks.py``), in the order they were added, its one channel to whatever
watches it: the parts of the problem that carry state along (an erodible layer, a
mobilisation state), then the run's files that read it and the checkpoint; a script adds
its own the same way. It knows no file format and no finite-element engine:
the solver, the mesh motion and the remesher are protocols (``simulation/parts.py``), so
the loop imports and runs without NGSolve; the stall test is ``simulation/stall.py``.

A step is accepted only when the move left a valid mesh, the nonlinear solve converged
and the step policy accepts its local error; otherwise the move is undone and the step
retried (after a remesh, or with a smaller dt). A remesh answers a move that tangles the
mesh, and a nonlinear iteration that fails on a degraded mesh: flat cells at a thin front
make the fixed-point iteration (3.2) cycle instead of converge.

A move that switches a boundary forcing on or off (the surface tension of section 3.4)
restarts the solver's history, as an ODE integrator restarts at a discontinuity: the
step starts from u^n and has no local error estimate, since the polynomial through the
past steps says nothing about a solution whose forcing just jumped; the step policy keeps
dt after it, and a rejected attempt gives the history back. Without the restart
each switch of the tension over a strong layer cost 3-6 steps rejected on Milne's
estimate, of 50-240 iterations each.
"""

from __future__ import annotations

import copy
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from enum import Enum
from typing import Any, ClassVar

from granflow.simulation.outcomes import (
    Failure,
    IterationReport,
    MeshingFailed,
    MoveFailure,
    RunResult,
)
from granflow.simulation.outputs import Callbacks
from granflow.simulation.parts import FlowStep, MeshMotion, Remesher
from granflow.simulation.remesh_errors import RemeshDefect, defect_message, mesher_failed
from granflow.simulation.rest import RestCriterion
from granflow.simulation.stall import STALL_STEPS, stall_check
from granflow.simulation.timestep import (
    AdaptiveStep,
    LocalError,
    RampedStep,
    StepPolicy,
    StepTooSmall,
)
from granflow.state.spec import (
    COUNT,
    TIME,
    Share,
    dataclass_of,
    list_of,
    mapping,
    may_lack,
    or_none,
    record,
    tuple_of,
)


class Rejection(Enum):
    """Why an attempted step was not accepted."""

    MOVE = "the mesh move was invalid"
    NOT_CONVERGED = Failure.NOT_CONVERGED.value
    NON_FINITE = Failure.NON_FINITE.value
    ERROR = "the local time error exceeded its tolerance"
    EXCEPTION = "the solver raised an error"


StopCriterion = Callable[["Simulation"], str | None]


@dataclass
class _Attempt:
    dt: float
    report: IterationReport | None = None
    rejection: Rejection | None = None
    move_failure: MoveFailure | None = None
    estimate: LocalError | None = None
    detail: str = ""
    restarted: bool = False   # the move switched a forcing: the history was restarted


@dataclass
class Simulation:
    solver: FlowStep
    steps_policy: StepPolicy
    t_end: float
    max_iterations: int
    mesh_motion: MeshMotion | None = None
    stop_criteria: Sequence[StopCriterion] = ()
    remesher: Remesher | None = None
    # what a remesh raises when the mesher cannot mesh the moved domain (the scenario adds
    # its mesher's own types, Netgen's NgException): retried or skipped; any other type
    # from a remesh is a defect and ends the run
    mesher_failures: tuple[type[Exception], ...] = (MeshingFailed,)
    velocity_floor: float = 0.0
    max_consecutive_rejections: int = 12
    stall_steps: int = STALL_STEPS       # 0: no stall test
    t: float = 0.0
    step: int = 0
    dt: float = 0.0
    attempted_dt: float = 0.0
    last_report: IterationReport | None = None
    last_estimate: LocalError | None = None
    rejected_steps: int = 0
    nonlinear_iterations: int = 0
    momentum_solves: int = 0
    skipped_remeshes: int = 0
    remesh_failures: dict[str, int] = field(default_factory=dict)   # error type -> count
    history_restarts: int = 0            # steps begun afresh after a jump of the forcing
    remeshed_moves: int = 0              # moves that would tangle, remeshed before the step
    remeshed_this_step: bool = False
    rejections: dict[str, int] = field(default_factory=dict)
    interrupt: str | None = None         # set (by a signal handler) to end the run cleanly
    elapsed_before: float = 0.0          # s of wall time spent before a resume
    callbacks: Callbacks = field(default_factory=Callbacks)   # name -> Callback, in order
    # its share of a checkpoint (``save_state``): what each member may be
    share: ClassVar[Share] = {
        "t": TIME, "step": COUNT, "dt": TIME, "rejected_steps": COUNT,
        "nonlinear_iterations": COUNT, "momentum_solves": COUNT,
        "skipped_remeshes": may_lack(COUNT), "remesh_failures": may_lack(mapping(COUNT)),
        "history_restarts": may_lack(COUNT),
        "remeshed_moves": may_lack(COUNT),
        "rejections": mapping(COUNT), "wall_time_s": TIME,
        "steps_policy": or_none(dataclass_of(AdaptiveStep, RampedStep)),
        "stop_criteria": list_of(or_none(record(RestCriterion.share))),
        "stall_window": may_lack(or_none(tuple_of(COUNT, TIME, mapping(COUNT))))}
    _start: float = field(default=0.0, repr=False)
    _rejections_in_row: int = field(default=0, repr=False)
    _remesh_error: str = field(default="", repr=False)
    _window: tuple[int, float, dict[str, int]] | None = field(default=None, repr=False)

    def replace(self, solver: FlowStep, mesh_motion: MeshMotion) -> None:
        """Continue on a new mesh (after a remesh): same time, counters and policy."""
        self.solver, self.mesh_motion = solver, mesh_motion

    @property
    def linear_solves(self) -> int:
        """Momentum solves (every solve with a factorised matrix) plus mesh-velocity solves."""
        return self.momentum_solves + getattr(self.mesh_motion, "velocity_solves", 0)

    # --- checkpoint (io/run_state.py) ------------------------------------------------
    def save_state(self) -> dict[str, Any]:
        """The loop's share of the run state: time, step, counters, policy, criteria."""
        return {
            "t": self.t, "step": self.step, "dt": self.dt,
            "rejected_steps": self.rejected_steps,
            "nonlinear_iterations": self.nonlinear_iterations,
            "momentum_solves": self.momentum_solves,
            "skipped_remeshes": self.skipped_remeshes,
            "remesh_failures": dict(self.remesh_failures),
            "history_restarts": self.history_restarts,
            "remeshed_moves": self.remeshed_moves,
            "rejections": dict(self.rejections),
            "wall_time_s": self.wall_time(),
            "steps_policy": copy.deepcopy(self.steps_policy),
            "stop_criteria": [c.save_state() if hasattr(c, "save_state") else None
                              for c in self.stop_criteria],
            "stall_window": self._window,   # where the stall test's window started
        }

    def restore_state(self, state: dict[str, Any]) -> None:
        for key in ("t", "step", "dt", "rejected_steps", "nonlinear_iterations",
                    "momentum_solves"):
            setattr(self, key, state[key])
        self.rejections = dict(state["rejections"])
        self.skipped_remeshes = int(state.get("skipped_remeshes", 0))
        self.remesh_failures = dict(state.get("remesh_failures", {}))
        self.history_restarts = int(state.get("history_restarts", 0))
        self.remeshed_moves = int(state.get("remeshed_moves", 0))
        self.elapsed_before = state["wall_time_s"]
        if state["steps_policy"] is not None:   # None: keep the policy of a changed config
            self.steps_policy = state["steps_policy"]
        for criterion, saved in zip(self.stop_criteria, state["stop_criteria"], strict=True):
            if saved is not None:
                criterion.restore_state(saved)  # type: ignore[attr-defined]
        window = state.get("stall_window")
        if window is not None:
            step, t, rejections = window
            self._window = (int(step), float(t), {str(k): int(v) for k, v in rejections.items()})

    def wall_time(self) -> float:
        """Wall time of the run so far, over all its sessions (resumes)."""
        running = time.perf_counter() - self._start if self._start else 0.0
        return self.elapsed_before + running

    def _attempt(self, dt: float, tol: float) -> _Attempt:
        """One try at a step of size dt (shortened by the mesh motion if it must)."""
        motion = self.mesh_motion
        proposed = dt
        if motion is not None:
            dt = motion.prepare(dt)
        attempt = _Attempt(dt)
        self.attempted_dt = dt
        if motion is not None:
            motion.move(dt)
            attempt.move_failure = motion.check()
            if self._remeshed_ahead(attempt.move_failure):   # the step, on the new mesh
                motion = self.mesh_motion
                assert motion is not None
                dt = attempt.dt = self.attempted_dt = motion.prepare(proposed)
                motion.move(dt)
                attempt.move_failure = motion.check()
            if attempt.move_failure is not None:
                attempt.rejection = Rejection.MOVE
                attempt.detail = attempt.move_failure.value
                return attempt
            if motion.forcing_jumped():
                self.solver.restart_history()   # see the module docstring
                attempt.restarted = True
        report = self.solver.solve_step(dt, tol, self.max_iterations, self.velocity_floor)
        attempt.report = report
        self.nonlinear_iterations += report.iterations
        self.momentum_solves += report.linear_solves
        if report.failure is Failure.NON_FINITE:
            attempt.rejection = Rejection.NON_FINITE
        elif report.failure is Failure.NOT_CONVERGED:
            attempt.rejection = Rejection.NOT_CONVERGED
            attempt.detail = (f"{report.iterations} iterations left a relative change of "
                              f"{report.relative_change:.2g}")
        else:
            raw = self.solver.local_error(dt)
            attempt.estimate = LocalError(*raw) if raw is not None else None
            if not self.steps_policy.judge(attempt.estimate):
                attempt.rejection = Rejection.ERROR
        return attempt

    def _remeshed_ahead(self, failure: MoveFailure | None) -> bool:
        """A move that would tangle the mesh (a fold, an inverted cell) is undone before
        any solve and answered by a remesh, after which the step is taken on the new mesh
        (``remeshed_moves``): a foreseen fold, not a rejected step. False when there is
        nothing to cure, no remesher, or this step has remeshed already."""
        if (failure is None or not failure.remeshable or self.remesher is None
                or self.remeshed_this_step or self.mesh_motion is None):
            return False
        self.mesh_motion.undo()
        self.remeshed_this_step = True
        if not self._remeshed():      # the mesher failed: then a smaller step
            return False
        self.remeshed_moves += 1
        return True

    def _remeshed(self) -> bool:
        """Remesh; False if the mesher could not (``mesher_failures``: counted, and the
        message of a run that then fails names it). Any other error is a defect: raised
        as ``RemeshDefect``, which ends the run at once."""
        assert self.remesher is not None
        try:
            self.remesher.remesh()
        except Exception as exc:
            self._remesh_failed(exc)
            if mesher_failed(exc, self.mesher_failures):
                return False
            raise RemeshDefect(defect_message(exc, self.step, self.t)) from exc
        return True

    def _remesh_failed(self, exc: Exception) -> None:
        """A remesh that raised: counted by the error's type (``remesh_failures`` in
        summary.json), so that a defect raising on every remesh is seen, not only a
        run going on with the mesh it had."""
        self._remesh_error = f"; remeshing failed: {type(exc).__name__}: {exc}"
        name = type(exc).__name__
        self.remesh_failures[name] = self.remesh_failures.get(name, 0) + 1

    def _undo(self) -> None:
        if self.mesh_motion is not None:
            self.mesh_motion.undo()
        self.solver.reject()

    def _reject(self, attempt: _Attempt) -> str | None:
        """Count, remesh or shrink dt; return a failure message if the run cannot go on."""
        assert attempt.rejection is not None
        self.rejected_steps += 1
        key = attempt.rejection.name.lower()
        self.rejections[key] = self.rejections.get(key, 0) + 1
        failure = attempt.move_failure
        tangled = failure is not None and failure.remeshable
        stalled = (attempt.rejection in (Rejection.NOT_CONVERGED, Rejection.NON_FINITE)
                   and self.remesher is not None and self.remesher.degraded())
        if (tangled or stalled) and self.remesher is not None and not self.remeshed_this_step:
            self.remeshed_this_step = True
            if self._remeshed():   # a tangling move or a stall: new mesh, same dt
                return None        # (else the mesher failed: smaller steps)
        self._rejections_in_row += 1
        try:
            if self._rejections_in_row > self.max_consecutive_rejections:
                raise StepTooSmall(f"{self._rejections_in_row} consecutive rejected steps")
            estimate = attempt.estimate if attempt.rejection is Rejection.ERROR else None
            self.steps_policy.rejected(attempt.dt, estimate)
        except StepTooSmall as exc:
            reason = attempt.rejection.value + (f" ({attempt.detail})" if attempt.detail else "")
            return (f"step {self.step + 1} at t = {self.t:.6g} s (dt = {attempt.dt:.3g} s) "
                    f"failed: {reason}{self._remesh_error}; {exc}. {self._advice(attempt)}")
        return None

    def _advice(self, attempt: _Attempt) -> str:
        step_key = getattr(self.steps_policy, "step_key", "time.dt_max")
        if attempt.rejection in (Rejection.NOT_CONVERGED, Rejection.NON_FINITE):
            return (f"Try a smaller {step_key}, numerics.linearization = 'hybrid' or 'newton', "
                    "or a larger numerics.max_iterations")
        return f"Try a smaller {step_key} or mesh.size"

    def _stalled(self) -> str | None:
        """The stall test (``simulation/stall.py``) after an accepted step."""
        if self.stall_steps <= 0:
            return None
        self._window, message = stall_check(
            self._window, self.stall_steps, self.step, self.t, self.dt, self.rejections,
            getattr(self.steps_policy, "dt_max", 0.0), self.t_end)
        return message

    def run(self) -> RunResult:
        self._start = time.perf_counter()
        status, message = "completed", f"reached t_end = {self.t_end:g} s"
        while self.t < self.t_end - 1e-12 * max(1.0, self.t_end):
            if self.interrupt is not None:
                status, message = "interrupted", (
                    f"{self.interrupt} at t = {self.t:.6g} s after step {self.step}")
                break
            dt, tol = self.steps_policy.propose(self.t)
            dt = min(dt, self.t_end - self.t)   # a policy restored from a run with another end
            self.attempted_dt = dt
            try:
                attempt = self._attempt(dt, tol)
            except RemeshDefect as defect:
                status, message = "failed", defect.message
                break
            except Exception as exc:  # a solver failure is a result, not a crash
                attempt = _Attempt(self.attempted_dt, rejection=Rejection.EXCEPTION,
                                   detail=f"{type(exc).__name__}: {exc}")
            if attempt.rejection is not None:
                self._undo()
                try:
                    failure = self._reject(attempt)
                except RemeshDefect as defect:
                    failure = defect.message
                if failure is not None:
                    status, message = "failed", failure
                    break
                continue
            self._accept(attempt)
            defect = self._remesh_if_due()
            reason = next((r for c in self.stop_criteria if (r := c(self)) is not None), None)
            stall = self._stalled() if reason is None else None
            for callback in list(self.callbacks.values()):
                callback(self)
            if defect is not None:      # the step stands and is written; the run stops
                status, message = "failed", defect
                break
            if reason is not None:
                status, message = "stopped", reason
                break
            if stall is not None:
                status, message = "failed", stall
                break
        wall = self.elapsed_before = self.wall_time()
        self._start = 0.0
        return RunResult(
            status=status, message=message, t_final=self.t, steps=self.step,
            rejected_steps=self.rejected_steps,
            nonlinear_iterations=self.nonlinear_iterations,
            linear_solves=self.linear_solves, wall_time_s=wall, rejections=dict(self.rejections),
            skipped_remeshes=self.skipped_remeshes, history_restarts=self.history_restarts,
            remesh_failures=dict(self.remesh_failures),
            remeshed_moves=self.remeshed_moves)

    def _accept(self, attempt: _Attempt) -> None:
        self._rejections_in_row = 0
        self.remeshed_this_step = False
        self._remesh_error = ""
        self.dt = attempt.dt
        self.solver.accept(self.dt)
        if self.mesh_motion is not None:
            self.mesh_motion.after_accept()
        self.steps_policy.accepted(self.dt, attempt.estimate, restarted=attempt.restarted)
        self.history_restarts += attempt.restarted
        self.t += self.dt
        self.step += 1
        self.last_report, self.last_estimate = attempt.report, attempt.estimate

    def _remesh_if_due(self) -> str | None:
        """The remesh the mesh's quality asks for after an accepted step. If the mesher
        cannot make it, the mesh in use is valid: the run goes on (a tangling step asks
        again). Returns the message of a defect, which ends the run."""
        if self.remesher is None or not self.remesher.needs_remesh():
            return None
        try:
            if not self._remeshed():
                self.skipped_remeshes += 1
        except RemeshDefect as defect:
            return defect.message
        return None
