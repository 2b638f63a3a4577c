"""The hysteretic friction's pure law (physics/hysteresis.py): the relaxation of the
mobilisation against its ODE's exact solution, and the blended stress against simple shear."""

import math
import warnings

import numpy as np
import pytest

from granflow.physics import DruckerPrager, MuI
from granflow.physics.hysteresis import Hysteretic, Relaxation, pick, relaxed

TAU_M, TAU_R, RATE = 0.02, 0.05, 1.0
LAW = Relaxation(mobilisation_time=TAU_M, rest_time=TAU_R, shear_rate=RATE)


def stepped(s0: float, rates: list[float], steps: list[float]) -> float:
    s = np.array([s0])
    for rate, dt in zip(rates, steps, strict=True):
        s = LAW.relax(s, np.array([rate]), dt)
    return float(s[0])


@pytest.mark.parametrize(("rate", "target", "tau"), [(5.0, 1.0, TAU_M), (0.5, 0.0, TAU_R)])
def test_relaxation_is_the_exact_solution_for_any_steps(rate: float, target: float,
                                                        tau: float) -> None:
    """Sheared (rate above the threshold) s -> 1 with tau_m, at rest s -> 0 with tau_r:
    uneven steps reproduce s(t) = target + (s0 - target) exp(-t / tau) to round-off."""
    steps = list(np.random.default_rng(1).uniform(1e-5, 0.02, 40))
    for s0 in (0.0, 0.3, 1.0):
        expected = relaxed(s0, target, tau, sum(steps))
        assert abs(stepped(s0, [rate] * len(steps), steps) - expected) < 1e-14
    assert abs(relaxed(0.0, 1.0, 0.02, 0.02) - (1 - math.exp(-1))) < 1e-15


def test_a_shear_history_against_the_piecewise_exact_solution() -> None:
    """Sheared for 0.03 s, then at rest for 0.07 s: exact to round-off with steps landing on
    the switch; a switch inside a step (the step's end decides its target, as after an
    accepted step) errs by at most dt / tau_m (the largest |ds/dt| times the shift of the
    switch), so first order."""
    switch = 0.03
    exact = relaxed(relaxed(0.0, 1.0, TAU_M, switch), 0.0, TAU_R, 0.1 - switch)

    def run(n: int, decide_at: float) -> float:
        dt = 0.1 / n
        times = (np.arange(n) + decide_at) * dt
        return stepped(0.0, [5.0 if t < switch else 0.0 for t in times], [dt] * n)

    assert abs(run(100, decide_at=0.5) - exact) < 1e-14
    errors = {n: abs(run(n, decide_at=1.0) - exact) for n in (13, 26, 52, 104, 208)}
    assert all(0 < e <= 0.1 / n / TAU_M for n, e in errors.items()), errors
    assert errors[208] < errors[13] / 4, errors


def test_state_stays_in_the_unit_interval() -> None:
    rng = np.random.default_rng(2)
    s = rng.uniform(0, 1, 1000)
    for _ in range(50):
        s = LAW.relax(s, rng.uniform(0, 2, 1000), float(rng.uniform(0, 1)))
        assert s.min() >= 0.0 and s.max() <= 1.0


def test_threshold_and_parameters_per_cell() -> None:
    assert list(LAW.sheared(np.array([0.5, 1.0, 1.5]))) == [False, False, True]
    cells = Relaxation(np.array([0.01, 0.1]), TAU_R, np.array([1.0, 10.0]))
    s = cells.relax(np.zeros(2), np.array([5.0, 5.0]), 0.01)
    assert abs(s[0] - (1 - math.exp(-1))) < 1e-15 and s[1] == 0.0
    assert list(pick(1.0, 2.0, np.array([0.0, 0.49, 0.5, 1.0]))) == [1.0, 1.0, 2.0, 2.0]
    with pytest.raises(ValueError, match="rest_time"):
        Relaxation(TAU_M, 0.0, RATE)


def test_blended_law_gives_the_blended_friction_in_simple_shear() -> None:
    """Simple shear u' = 2 1/s under p = 300 Pa: the shear stress is eta u' + mu p with
    mu = (1 - s) tan(start) + s tan(flow) (|Du| = u' / sqrt(2), stress m |Du| / sqrt(2)),
    within the regularisation (eps = 1e-8: 1e-16 relative)."""
    eta, p, rate = 0.5, 300.0, 2.0
    flow = DruckerPrager(eta, 20.0, 1e-8)
    start = DruckerPrager(eta, 25.0, 1e-8)
    for s in (0.0, 0.3, 1.0):
        law = Hysteretic(flow=flow, start=start, relaxation=LAW, mobilisation=s)
        stress = law.effective_viscosity(rate / math.sqrt(2), p) * rate / 2
        mu = (1 - s) * math.tan(math.radians(25)) + s * math.tan(math.radians(20))
        assert abs(stress - (eta * rate + mu * p)) < 1e-12 * stress
    mu_i = MuI(eta, 20.9, 32.76, 0.279, 5e-4, 2500.0, 1e-8)
    start = DruckerPrager(eta, 25.5, 1e-8)
    law = Hysteretic(flow=mu_i, start=start, relaxation=LAW, mobilisation=0.25)
    inertial = rate * 5e-4 / math.sqrt(p / 2500.0)
    mu = 0.75 * math.tan(math.radians(25.5)) + 0.25 * float(mu_i.friction(inertial))
    stress = law.effective_viscosity(rate / math.sqrt(2), p) * rate / 2
    assert abs(stress - (eta * rate + mu * p)) < 1e-9 * stress


def test_start_and_flow_laws_must_match() -> None:
    with pytest.raises(ValueError, match="viscosity and eps"):
        Hysteretic(flow=DruckerPrager(1.0, 20.0, 1e-6), start=DruckerPrager(0.5, 25.0, 1e-6),
                   relaxation=LAW, mobilisation=0.0)
    with pytest.raises(ValueError, match="initial_mobilisation"):
        Hysteretic(flow=DruckerPrager(1.0, 20.0, 1e-6), start=DruckerPrager(1.0, 25.0, 1e-6),
                   relaxation=LAW, mobilisation=0.0, initial=1.5)


def test_extreme_times_relax_without_a_numpy_warning() -> None:
    """tau of 1e-300 s (its floor is 1e-6; the law itself takes any positive one) over a
    step of 1 s: dt / tau overflows, s reaches its target, and numpy says nothing."""
    relaxation = Relaxation(mobilisation_time=1e-300, rest_time=1e-300, shear_rate=1.0)
    with np.errstate(all="raise"), warnings.catch_warnings():
        warnings.simplefilter("error")
        s = relaxation.relax(np.array([0.2, 0.7]), np.array([5.0, 0.0]), dt=1.0)
    assert s.tolist() == [1.0, 0.0]


def test_a_yield_ratio_beyond_the_floats_is_inf_without_a_numpy_warning() -> None:
    from granflow.diagnostics.stress import yield_ratio

    with np.errstate(all="raise"), warnings.catch_warnings():
        warnings.simplefilter("error")
        ratio = yield_ratio(np.array([1e10, 1.0, 1.0]), np.array([1e-300, 2.0, 0.0]))
    assert ratio[0] == math.inf and ratio[1] == 0.5 and math.isnan(ratio[2])
