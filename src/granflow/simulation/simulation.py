"""The time loop: mesh velocity -> move -> nonlinear solve -> accept/reject (section 3.3).

It owns the stop criteria and says why it stopped; observers read the state after each
accepted step and never change it. It knows no file format.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

from granflow.fem.flow import FlowSolver
from granflow.fem.nonlinear import IterationReport


class StepPolicy(Protocol):
    def propose(self, t: float) -> tuple[float, float]: ...
    def accepted(self, dt: float) -> None: ...
    def rejected(self, dt: float) -> None: ...


class MeshMotion(Protocol):
    """Computes w^n, limits dt, moves the mesh, checks it, and can undo the move."""

    def prepare(self, dt: float) -> float: ...
    def move(self, dt: float) -> None: ...
    def check(self) -> str | None: ...
    def undo(self) -> None: ...
    def after_accept(self) -> None: ...


class Remesher(Protocol):
    """Replaces the mesh (and with it solver and mesh motion) when it has degraded."""

    def needs_remesh(self) -> bool: ...
    def remesh(self) -> None: ...


REMESHABLE = ("inverted", "self-intersects")  # move failures a new mesh can cure
Observer = Callable[["Simulation"], None]
StopCriterion = Callable[["Simulation"], str | None]


@dataclass
class RunResult:
    """Why and where the loop stopped, and what it cost."""

    status: str                      # completed | stopped | failed
    message: str
    t_final: float
    steps: int
    rejected_steps: int
    nonlinear_iterations: int
    linear_solves: int
    unconverged_steps: int
    wall_time_s: float


@dataclass
class Simulation:
    solver: FlowSolver
    steps_policy: StepPolicy
    t_end: float
    max_iterations: int
    mesh_motion: MeshMotion | None = None
    observers: Sequence[Observer] = ()
    stop_criteria: Sequence[StopCriterion] = ()
    remesher: Remesher | None = None
    velocity_floor: float = 0.0
    max_consecutive_rejections: int = 12
    t: float = 0.0
    step: int = 0
    dt: float = 0.0
    attempted_dt: float = 0.0
    last_report: IterationReport | None = None
    rejected_steps: int = 0
    nonlinear_iterations: int = 0
    unconverged_steps: int = 0
    remeshed_this_step: bool = False
    _rejections_in_row: int = field(default=0, repr=False)
    _remesh_error: str = field(default="", repr=False)

    def replace(self, solver: FlowSolver, mesh_motion: MeshMotion) -> None:
        """Continue on a new mesh (after a remesh): same time, counters and policy."""
        self.solver, self.mesh_motion = solver, mesh_motion

    @property
    def linear_solves(self) -> int:
        """Momentum solves (one per fixed-point iteration) plus mesh-velocity solves."""
        return self.nonlinear_iterations + getattr(self.mesh_motion, "velocity_solves", 0)

    def _attempt(self, dt: float, tol: float) -> tuple[IterationReport | None, str | None]:
        """One try at a step of size dt (shortened by the mesh motion if it must)."""
        motion = self.mesh_motion
        if motion is not None:
            dt = motion.prepare(dt)
        self.attempted_dt = dt
        if motion is not None:
            motion.move(dt)
            problem = motion.check()
            if problem is not None:
                motion.undo()
                return None, problem
        self.dt = dt
        report = self.solver.solve_step(dt, tol, self.max_iterations, self.velocity_floor)
        self.nonlinear_iterations += report.iterations
        if not report.finite:
            if motion is not None:
                motion.undo()
            self.solver.reject()
            return report, "the nonlinear iteration produced non-finite values"
        return report, None

    def run(self) -> RunResult:
        start = time.perf_counter()
        status, message = "completed", f"reached t_end = {self.t_end:g} s"
        while self.t < self.t_end - 1e-12 * max(1.0, self.t_end):
            dt, tol = self.steps_policy.propose(self.t)
            self.attempted_dt = dt
            try:
                report, problem = self._attempt(dt, tol)
            except Exception as exc:  # a solver failure is a result, not a crash
                report, problem = None, f"{type(exc).__name__}: {exc}"
                if self.mesh_motion is not None:
                    self.mesh_motion.undo()
                self.solver.reject()
            if problem is not None:
                self.rejected_steps += 1
                self._rejections_in_row += 1
                if (self.remesher is not None and not self.remeshed_this_step
                        and any(word in problem for word in REMESHABLE)):
                    self.remeshed_this_step = True
                    try:
                        self.remesher.remesh()  # a tangling move: new mesh, same dt
                        continue
                    except RuntimeError as exc:  # then fall back to smaller steps
                        self._remesh_error = f"; remeshing failed: {exc}"
                try:
                    if self._rejections_in_row > self.max_consecutive_rejections:
                        raise RuntimeError("too many consecutive rejected steps")
                    self.steps_policy.rejected(self.attempted_dt)
                    continue
                except RuntimeError as exc:
                    status = "failed"
                    message = (f"step {self.step + 1} at t = {self.t:.6g} s (dt = {dt:.3g} s) "
                               f"failed: {problem}{self._remesh_error}; {exc}. Try a smaller "
                               "time.dt_max or mesh.size, or a larger numerics.max_iterations")
                    break
            assert report is not None
            self._rejections_in_row = 0
            self.remeshed_this_step = False
            self._remesh_error = ""
            if not report.converged:
                self.unconverged_steps += 1
            self.solver.accept()
            if self.mesh_motion is not None:
                self.mesh_motion.after_accept()
            self.steps_policy.accepted(self.dt)
            self.t += self.dt
            self.step += 1
            self.last_report = report
            if self.remesher is not None and self.remesher.needs_remesh():
                self.remesher.remesh()
            for observer in self.observers:
                observer(self)
            reason = next((r for c in self.stop_criteria if (r := c(self)) is not None), None)
            if reason is not None:
                status, message = "stopped", reason
                break
        return RunResult(
            status=status, message=message, t_final=self.t, steps=self.step,
            rejected_steps=self.rejected_steps,
            nonlinear_iterations=self.nonlinear_iterations,
            linear_solves=self.linear_solves, unconverged_steps=self.unconverged_steps,
            wall_time_s=time.perf_counter() - start)

