"""The time loop's handling of failed moves: remesh once, then smaller steps, then a
clear failure naming the time, the step and what to change; and its restart of the
solver's history when a move switches a forcing."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from granflow.simulation.outcomes import IterationReport, MeshingFailed, MoveFailure
from granflow.simulation.simulation import STALL_STEPS, Simulation
from granflow.simulation.timestep import AdaptiveStep, RampedStep, fixed_step


class StubSolver:
    """Converges at once; the loop only needs the report."""

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        return IterationReport(converged=True, iterations=1, relative_change=0.0)

    def local_error(self, dt: float) -> tuple[float, float] | None:
        return None

    def accept(self, dt: float | None = None) -> None: ...
    def reject(self) -> None: ...
    def restart_history(self) -> None: ...


@dataclass
class FoldingMotion:
    """A mesh motion whose first ``failures`` moves fold the surface through itself."""

    failures: int
    moves: int = 0

    def prepare(self, dt: float) -> float:
        return dt

    def move(self, dt: float) -> None:
        self.moves += 1

    def check(self) -> MoveFailure | None:
        if self.moves <= self.failures:
            return MoveFailure.SELF_INTERSECTS
        return None

    def undo(self) -> None: ...
    def after_accept(self) -> None: ...

    def forcing_jumped(self) -> bool:
        return False


@dataclass
class StubRemesher:
    fails: bool
    calls: int = 0
    wanted: bool = False     # the mesh's quality asks for a remesh after every step

    def needs_remesh(self) -> bool:
        return self.wanted

    def degraded(self) -> bool:
        return False

    def remesh(self) -> None:
        self.calls += 1
        if self.fails:
            raise MeshingFailed("meshing failed")


def loop(motion: FoldingMotion, remesher: StubRemesher) -> Simulation:
    return Simulation(solver=StubSolver(), steps_policy=fixed_step(0.01, 1e-3, 1e-3),  # type: ignore[arg-type]
                      t_end=0.01, max_iterations=10, mesh_motion=motion, remesher=remesher)


def test_a_folding_move_is_cured_by_one_remesh_at_the_same_dt() -> None:
    """The fold is found before the step is solved: the step is taken on the new mesh,
    not rejected and retried."""
    remesher = StubRemesher(fails=False)
    result = loop(FoldingMotion(failures=1), remesher).run()
    assert result.status == "completed" and result.steps == 10
    assert remesher.calls == 1 and result.rejected_steps == 0
    assert result.remeshed_moves == 1


def test_a_move_no_remesh_can_cure_fails_with_time_step_and_advice() -> None:
    remesher = StubRemesher(fails=True)
    result = loop(FoldingMotion(failures=10**6), remesher).run()
    assert result.status == "failed" and result.steps == 0
    assert remesher.calls == 1                     # tried once, then smaller steps
    assert result.rejected_steps == 13             # 12 consecutive rejections allowed
    for part in ("step 1", "t = 0 s", "self-intersects", "remeshing failed",
                 "13 consecutive rejected steps", "time.dt"):
        assert part in result.message


def test_a_quality_remesh_that_fails_leaves_the_run_on_its_valid_mesh() -> None:
    """A remesh asked for by the quality rule after an accepted step that the mesher cannot
    make is skipped and counted: the mesh in use passed its checks."""
    remesher = StubRemesher(fails=True, wanted=True)
    result = loop(FoldingMotion(failures=0), remesher).run()
    assert result.status == "completed" and result.steps == 10
    assert remesher.calls == 10 and result.skipped_remeshes == 10
    assert result.remesh_failures == {"MeshingFailed": 10}


class BrokenRemesher(StubRemesher):
    """A remesher with a defect: it raises what no mesher raises."""

    def remesh(self) -> None:
        self.calls += 1
        raise TypeError("transfer() takes 3 positional arguments but 4 were given")


def test_a_remesh_raising_a_defect_after_a_step_stops_the_run_at_once() -> None:
    """A quality remesh that raises a TypeError ends the run after the step that asked
    for it (kept, as its outputs are), with when, where and what to do."""
    remesher = BrokenRemesher(fails=True, wanted=True)
    result = loop(FoldingMotion(failures=0), remesher).run()
    assert result.status == "failed" and result.steps == 1 and remesher.calls == 1
    assert result.skipped_remeshes == 0 and result.remesh_failures == {"TypeError": 1}
    for part in ("after step 1 at t = 0.001 s", "TypeError in remesh (test_time_loop.py:",
                 "takes 3 positional arguments", "a defect in granflow", "config.toml"):
        assert part in result.message


def test_a_remesh_raising_a_defect_for_a_folding_move_stops_the_run_at_once() -> None:
    """Not retried with smaller steps as a mesher's failure is."""
    remesher = BrokenRemesher(fails=True)
    result = loop(FoldingMotion(failures=10**6), remesher).run()
    assert result.status == "failed" and result.steps == 0 and remesher.calls == 1
    assert result.rejected_steps == 0
    assert "after step 0 at t = 0 s: remeshing raised TypeError" in result.message


class OtherMesherError(Exception):
    """A mesher's own error type that is no RuntimeError (as Netgen's NgException)."""


def test_a_mesher_failure_of_the_scenarios_type_is_retried_and_any_other_is_not() -> None:
    class Refusing(StubRemesher):
        def remesh(self) -> None:
            self.calls += 1
            raise OtherMesherError("meshing failed")

    sim = loop(FoldingMotion(failures=0), Refusing(fails=True, wanted=True))
    sim.mesher_failures = (MeshingFailed, OtherMesherError)
    result = sim.run()
    assert result.status == "completed" and result.skipped_remeshes == 10
    assert result.remesh_failures == {"OtherMesherError": 10}
    result = loop(FoldingMotion(failures=0), Refusing(fails=True, wanted=True)).run()
    assert result.status == "failed" and result.steps == 1


def test_a_not_implemented_carrier_is_a_defect_though_a_runtime_error() -> None:
    class Unfinished(StubRemesher):
        def remesh(self) -> None:
            raise NotImplementedError("a piecewise-constant field is not carried")

    sim = loop(FoldingMotion(failures=0), Unfinished(fails=True, wanted=True))
    sim.mesher_failures = (RuntimeError,)
    result = sim.run()
    assert result.status == "failed" and "NotImplementedError" in result.message


class TinyStepSolver(StubSolver):
    """Converges only for steps under 1e-8 s: a run that would crawl forever."""

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        if dt < 1e-8:
            return IterationReport(converged=True, iterations=1, relative_change=0.0)
        return IterationReport(converged=False, iterations=max_iterations, relative_change=1.0)


def test_a_run_that_only_advances_by_tiny_steps_fails_as_stalled() -> None:
    sim = Simulation(solver=TinyStepSolver(), steps_policy=fixed_step(0.01, 1e-3, 1e-3),  # type: ignore[arg-type]
                     t_end=0.01, max_iterations=10, max_consecutive_rejections=30)
    result = sim.run()
    assert result.status == "failed" and result.steps == STALL_STEPS + 1
    assert result.t_final < 1e-3                     # less than one dt_max in 1,000 steps
    for part in ("stalled at t = ", f"step {STALL_STEPS + 1}", "less than one dt_max",
                 "not_converged", "numerics.max_iterations"):
        assert part in result.message


class ErrorControlledSolver(StubSolver):
    """Converges at once; its local error asks for steps of about 1e-5 s."""

    def local_error(self, dt: float) -> tuple[float, float] | None:
        return 1e-2 * (dt / 1e-5) ** 2, 1.0      # error_tol 1e-2 x speed 1 at dt = 1e-5


@pytest.mark.parametrize("policy", ["slow ramp", "error control far below dt_max"])
def test_the_stall_test_leaves_small_steps_the_policy_chose_alone(policy: str) -> None:
    if policy == "slow ramp":   # the paper's ramp (3.1) from 1e-8 s, but growing by 1.001
        steps = RampedStep(t_end=2e-4, dt_init=1e-8, dt_max=1e-4, growth=1.001, tol=1e-3,
                           tol_init=1e-3)
        solver: StubSolver = StubSolver()
    else:
        steps = AdaptiveStep(t_end=0.03, dt_init=1e-5, dt_max=1.0, tol=1e-3, error_tol=1e-2,
                             error_floor=1e-3)
        solver = ErrorControlledSolver()
    sim = Simulation(solver=solver, steps_policy=steps, t_end=steps.t_end,  # type: ignore[arg-type]
                     max_iterations=10)
    result = sim.run()
    assert result.status == "completed", result.message
    assert result.steps > 2 * STALL_STEPS          # many small steps, none of them stalled


class RecordingSolver(StubSolver):
    def __init__(self) -> None:
        self.events: list[str] = []

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        self.events.append("solve")
        return super().solve_step(dt, tol, max_iterations, velocity_floor)

    def restart_history(self) -> None:
        self.events.append("restart")


@dataclass
class SwitchingMotion(FoldingMotion):
    """Switches a forcing (the surface tension) on at its 3rd move and off at its 7th."""

    def forcing_jumped(self) -> bool:
        return self.moves in (3, 7)


def test_a_move_that_switches_the_forcing_restarts_the_history_before_the_solve() -> None:
    solver = RecordingSolver()
    sim = Simulation(solver=solver, steps_policy=fixed_step(0.01, 1e-3, 1e-3),  # type: ignore[arg-type]
                     t_end=0.01, max_iterations=10, mesh_motion=SwitchingMotion(failures=0))
    result = sim.run()
    assert result.status == "completed" and result.history_restarts == 2
    assert solver.events[:4] == ["solve", "solve", "restart", "solve"]
    assert solver.events.count("restart") == 2 and solver.events.count("solve") == 10
    assert sim.save_state()["history_restarts"] == 2


def test_a_loop_state_of_an_earlier_version_with_its_unconverged_counter_restores() -> None:
    """Checkpoints written before the always-zero ``unconverged_steps`` counter was dropped
    still carry it: a resume ignores it and continues the counters it knows."""
    sim = Simulation(solver=RecordingSolver(), steps_policy=fixed_step(0.01, 1e-3, 1e-3),  # type: ignore[arg-type]
                     t_end=0.01, max_iterations=10)
    sim.run()
    state = sim.save_state() | {"unconverged_steps": 0}
    twin = Simulation(solver=RecordingSolver(), steps_policy=fixed_step(0.01, 1e-3, 1e-3),  # type: ignore[arg-type]
                      t_end=0.01, max_iterations=10)
    twin.restore_state(state)
    assert (twin.t, twin.step, twin.nonlinear_iterations) == (sim.t, sim.step,
                                                               sim.nonlinear_iterations)
    assert "unconverged_steps" not in twin.save_state()
