"""The first iterate of a step (``numerics.initial_guess``): "auto" starts from
whichever of (u^n, p^n) and the linear extrapolation predicted the last accepted step
better; after a restart of the history (a jump of the forcing) every choice starts from
(u^n, p^n) and the step has no error estimate."""

from __future__ import annotations

import ngsolve as ngs
import pytest

from granflow.fem.flow import FlowSolver
from granflow.fem.flow_factory import (
    Discretisation,
    FlowSpec,
    GivenLaw,
    SolverChoice,
    Terms,
    build_flow,
)
from granflow.geometry.mesh import BED, SURFACE, WALL, polygon_mesh
from granflow.physics import DruckerPrager

DT = 1e-3


def _solver(initial_guess: str, linearization: str = "picard",
            scheme: str = "implicit-euler") -> FlowSolver:
    mesh = polygon_mesh([(0, 0), (0.2, 0), (0.2, 0.1), (0, 0.1)],
                        [BED, SURFACE, SURFACE, WALL], 0.05)
    return build_flow(mesh, FlowSpec(
        GivenLaw(DruckerPrager(1.0, 25.5, 1e-3), 1550.0), Terms((0.0, -9.81)),
        Discretisation(scheme=scheme),
        SolverChoice(linearization, initial_guess=initial_guess)))


def _history(s: FlowSolver, speeds: tuple[float, float, float]) -> None:
    """Accept two steps with uniform velocities (speed, 0): u^{n-1}, u^n, then u^{n+1}
    as the solution of the step about to be accepted."""
    s.set_state(ngs.CF((speeds[0], 0.0)), ngs.CF(0.0))
    for speed in speeds[1:]:
        s.solution.components[0].Set(ngs.CF((speed, 0.0)))
        s.nonlinear.prepare_norm()
        s.accept(DT)


@pytest.mark.parametrize(("speeds", "extrapolate"), [
    ((0.0, 1.0, 2.0), True),      # steady acceleration: the extrapolation is exact
    ((0.0, 1.0, 1.1), False),     # sudden stop: u^n is the better guess
    ((1.0, 0.0, 1.0), False),     # period-2 noise: the extrapolation doubles it
])
def test_auto_follows_the_better_predictor(speeds: tuple[float, float, float],
                                           extrapolate: bool) -> None:
    s = _solver("auto")
    _history(s, speeds)
    assert s.first_iterate_extrapolated() is extrapolate
    restored = _solver("auto")      # a checkpoint carries the choice
    restored.restore_history(s.save_history())
    assert restored.first_iterate_extrapolated() is extrapolate


def test_fixed_choices_do_not_depend_on_the_history() -> None:
    for guess, linearization, expected in [("previous", "picard", False),
                                           ("extrapolated", "picard", True),
                                           ("previous", "newton", True)]:
        s = _solver(guess, linearization)
        _history(s, (0.0, 1.0, 1.1))
        assert s.first_iterate_extrapolated() is expected


def test_auto_starts_the_step_from_the_chosen_guess() -> None:
    s = _solver("auto")
    _history(s, (1.0, 0.0, 1.0))   # u^n = 1: the step starts there, not from 2
    s.nonlinear.solve_picard = lambda *args: None      # only the first iterate matters
    s.solve_step(DT, 1e-6, 1)
    u = s.solution.components[0]
    assert ngs.Integrate(u[0], s.mesh) / s.volume() == pytest.approx(1.0, rel=1e-12)


def test_a_restarted_history_starts_from_the_last_state_without_an_estimate() -> None:
    """Also BDF2's third state, and a rejected step gives the history back."""
    s = _solver("extrapolated", scheme="bdf2")
    _history(s, (0.0, 1.0, 2.0))   # u^n = 2, u^{n-1} = 1: the extrapolation gives 3
    assert s.scheme.name == "bdf2" and s.scheme.dt_older > 0
    assert s.local_error(DT) is not None
    s.restart_history()
    assert s.local_error(DT) is None
    assert s.scheme.dt_previous == 0 and s.scheme.dt_older == 0
    s.reject()
    assert s.scheme.dt_previous == DT and s.scheme.dt_older == DT
    assert s.local_error(DT) is not None
    s.restart_history()
    s.nonlinear.solve_picard = lambda *args: None
    s.solve_step(DT, 1e-6, 1)
    u = s.solution.components[0]
    assert ngs.Integrate(u[0], s.mesh) / s.volume() == pytest.approx(2.0, rel=1e-12)
