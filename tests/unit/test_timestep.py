"""Step policies: the paper's ramp, the fixed step and the error-controlled step, and the
loop's rule that a step whose nonlinear solve did not converge is never accepted."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

from granflow.simulation.outcomes import IterationReport
from granflow.simulation.rest import RestCriterion
from granflow.simulation.simulation import Simulation
from granflow.simulation.timestep import (
    MAX_GROWTH,
    AdaptiveStep,
    LocalError,
    RampedStep,
    StepTooSmall,
    fixed_step,
)


def test_ramp_grows_by_its_factor_up_to_dt_max() -> None:
    ramp = RampedStep(t_end=1.0, dt_init=1e-3, dt_max=1.5e-3, growth=1.1, tol=1e-4,
                      tol_init=1e-6)
    taken = []
    t = 0.0
    for _ in range(8):
        dt, _ = ramp.propose(t)
        taken.append(dt)
        ramp.accepted(dt)
        t += dt
    assert taken[:3] == pytest.approx([1e-3, 1.1e-3, 1.21e-3])
    assert taken[-1] == pytest.approx(1.5e-3)
    assert ramp.current_tol == pytest.approx(1e-6 * 1.1**8)  # tol ramps by the same factor


def test_a_halved_fixed_step_recovers_even_before_its_first_acceptance() -> None:
    policy = fixed_step(t_end=1.0, dt=0.01, tol=1e-3)
    policy.rejected(0.01)                                   # the very first attempt fails
    steps = []
    t = 0.0
    for _ in range(4):
        dt, _ = policy.propose(t)
        steps.append(dt)
        policy.accepted(dt)
        t += dt
    assert steps == pytest.approx([0.005, 0.01, 0.01, 0.01])


def test_a_step_shortened_by_an_output_time_keeps_the_ramp() -> None:
    ramp = fixed_step(t_end=1.0, dt=0.1, tol=1e-3, stops=[0.25])
    assert ramp.propose(0.2)[0] == pytest.approx(0.05)      # lands on the output time
    ramp.accepted(0.05)
    assert ramp.propose(0.25)[0] == pytest.approx(0.1)


def test_ramp_gives_up_below_the_floor() -> None:
    ramp = fixed_step(t_end=1.0, dt=1e-13, tol=1e-3)
    with pytest.raises(StepTooSmall):
        ramp.rejected(1e-14)


def adaptive(**kw: float) -> AdaptiveStep:
    args = dict(t_end=1.0, dt_init=1e-3, dt_max=0.1, tol=1e-4, error_tol=1e-2,
                error_floor=1e-3)
    args.update(kw)
    return AdaptiveStep(**args)


def test_adaptive_accepts_within_tolerance_and_grows_at_most_twice() -> None:
    policy = adaptive()
    small = LocalError(error=1e-9, speed=1.0)
    assert policy.judge(small)
    policy.accepted(1e-3, small)
    assert policy.next_dt == pytest.approx(MAX_GROWTH * 1e-3)


def test_a_step_that_restarted_the_history_keeps_dt() -> None:
    """No estimate after a jump of the forcing says nothing about the error: dt is kept
    (the first step of a run, also without an estimate, grows)."""
    restarted, first = adaptive(), adaptive()
    restarted.accepted(1e-3, None, restarted=True)
    first.accepted(1e-3, None)
    assert restarted.next_dt == pytest.approx(1e-3)
    assert first.next_dt == pytest.approx(MAX_GROWTH * 1e-3)


def test_adaptive_rejects_a_large_error_and_shrinks_by_the_square_root() -> None:
    policy = adaptive()
    large = LocalError(error=4e-2, speed=1.0)           # 4 x the tolerance 1e-2 x 1 m/s
    assert not policy.judge(large)
    policy.rejected(1e-3, large)
    assert policy.next_dt == pytest.approx(1e-3 * 0.9 / 2)


def test_adaptive_error_is_absolute_below_the_floor_speed() -> None:
    policy = adaptive()
    at_rest = LocalError(error=5e-6, speed=1e-6)         # 5e-6 <= 1e-2 x 1e-3
    assert policy.judge(at_rest)
    assert not policy.judge(LocalError(error=2e-5, speed=1e-6))


def test_adaptive_step_is_capped_and_hits_stops() -> None:
    policy = adaptive(dt_init=0.08, stops=[0.1])
    policy.accepted(0.08, LocalError(0.0, 1.0))
    assert policy.next_dt == pytest.approx(0.1)             # dt_max
    assert policy.propose(0.08)[0] == pytest.approx(0.02)   # up to the output time


def test_a_slow_flow_raises_the_cap_up_to_dt_max_slow_and_a_fast_one_keeps_dt_max() -> None:
    """The cap is the step in which the RMS speed carries the flow slow_travel, between
    dt_max and dt_max_slow; without dt_max_slow it is dt_max whatever the speed."""
    def grown(policy: AdaptiveStep, speed: float) -> float:
        for _ in range(20):           # no error: the controller grows to the cap
            policy.accepted(policy.next_dt, LocalError(0.0, speed))
        return policy.next_dt

    slow = dict(dt_init=0.001, dt_max=0.01, t_end=100.0)
    assert grown(adaptive(**slow, dt_max_slow=0.04, slow_travel=1e-3), 0.05) == \
        pytest.approx(0.02)                                   # 1 mm at 5 cm/s
    assert grown(adaptive(**slow, dt_max_slow=0.04, slow_travel=1e-3), 1e-4) == \
        pytest.approx(0.04)                                   # creeping: dt_max_slow
    assert grown(adaptive(**slow, dt_max_slow=0.04, slow_travel=1e-3), 1.0) == \
        pytest.approx(0.01)                                   # fast: dt_max
    assert grown(adaptive(**slow), 1e-4) == pytest.approx(0.01)   # off


def test_adaptive_keeps_its_step_after_a_step_shortened_by_a_landing() -> None:
    policy = adaptive(dt_init=0.01)
    policy.accepted(0.002, LocalError(1e-6, 1.0))           # shortened, small error
    assert policy.next_dt == pytest.approx(0.01)


def test_a_failed_nonlinear_solve_halves_the_adaptive_step() -> None:
    policy = adaptive(dt_init=0.01)
    policy.rejected(0.01, None)
    assert policy.next_dt == pytest.approx(0.005)


@dataclass
class FlakySolver:
    """Fails to converge on the first ``failures`` solves, then converges at once."""

    failures: int
    calls: list[float] = field(default_factory=list)

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        self.calls.append(dt)
        converged = len(self.calls) > self.failures
        return IterationReport(converged=converged, iterations=max_iterations,
                               relative_change=0.0 if converged else 0.5)

    def local_error(self, dt: float) -> tuple[float, float] | None:
        return None

    def accept(self, dt: float | None = None) -> None: ...
    def reject(self) -> None: ...


def test_an_unconverged_step_is_retried_smaller_never_accepted() -> None:
    solver = FlakySolver(failures=2)
    sim = Simulation(solver=solver, steps_policy=fixed_step(0.04, 0.01, 1e-3),  # type: ignore[arg-type]
                     t_end=0.04, max_iterations=5)
    result = sim.run()
    assert result.status == "completed"
    assert result.rejected_steps == 2 and result.rejections == {"not_converged": 2}
    assert solver.calls[:3] == pytest.approx([0.01, 0.005, 0.0025])
    assert result.t_final == pytest.approx(0.04)


def test_a_run_that_never_converges_fails_naming_the_step_key() -> None:
    sim = Simulation(solver=FlakySolver(failures=10**6),                    # type: ignore[arg-type]
                     steps_policy=fixed_step(0.04, 0.01, 1e-3), t_end=0.04, max_iterations=5)
    result = sim.run()
    assert result.status == "failed"
    assert "did not converge" in result.message and "time.dt" in result.message
    assert "time.dt_max" not in result.message              # the user fixed time.dt


class Clock:
    def __init__(self) -> None:
        self.t = 0.0


def test_rest_needs_motion_first_then_a_full_window_below_the_fraction() -> None:
    fractions = iter([0.0, 0.0, 0.5, 0.2, 5e-4, 5e-4, 5e-4, 5e-4])
    rest = RestCriterion(lambda: next(fractions), fraction=1e-3, duration=0.2)
    clock, reasons = Clock(), []
    for k in range(8):
        clock.t = 0.1 * k
        reasons.append(rest(clock))                           # type: ignore[arg-type]
    assert reasons[:6] == [None] * 6                          # at rest since 0.4, for < 0.2 s
    assert reasons[6] is not None and "t = 0.4 s" in reasons[6]
