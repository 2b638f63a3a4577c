"""The policy of the primal-dual iteration in ``NonlinearSolver._picard``: when the
correction switches on, that a round of corrected iterations which does not pay is undone,
and that convergence is judged on a plain iteration of (3.2). Scripted stand-ins for the
linear system and the dual variable make every change known in advance."""

import math

import ngsolve as ngs
import pytest
from netgen.geom2d import unit_square

from granflow.fem.nonlinear import PRIMAL_DUAL_AFTER, PRIMAL_DUAL_ROUND, NonlinearSolver
from granflow.fem.spaces import taylor_hood


class ScriptedSystem:
    """x^{k+1} = x^k + d e, e a unit velocity: plain iterations contract d by ``plain``,
    corrected ones multiply the last d by ``corrected``."""

    def __init__(self, direction: ngs.BaseVector, plain: float, corrected: float) -> None:
        self.e, self.plain, self.corrected = direction, plain, corrected
        self.d, self.flags = 1e-3, []

    def prepare(self) -> None:
        pass

    def iterate(self, out: ngs.BaseVector, corrected: bool = False) -> None:
        self.flags.append(corrected)
        self.d *= self.corrected if corrected else self.plain
        out.data = self.state + self.d * self.e


class CountingDual:
    def __init__(self) -> None:
        self.starts = self.updates = 0

    def prepare(self) -> None:
        pass

    def start(self) -> None:
        self.starts += 1

    def update(self, solution: ngs.BaseVector) -> None:
        self.updates += 1


def solver(plain: float, corrected: float) -> tuple[NonlinearSolver, ScriptedSystem]:
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.5))
    state = ngs.GridFunction(taylor_hood(mesh))
    direction = ngs.GridFunction(state.space)
    direction.components[0].Set(ngs.CF((1.0, 0.0)))        # ||e|| = 1 on the unit square
    system = ScriptedSystem(direction.vec, plain, corrected)
    system.state = state.vec
    nonlinear = NonlinearSolver(system, None, state, CountingDual())  # type: ignore[arg-type]
    return nonlinear, system


def velocity_x(nonlinear: NonlinearSolver) -> float:
    return ngs.Integrate(nonlinear.state.components[0][0], nonlinear.state.space.mesh)


def test_a_round_that_does_not_pay_is_undone_and_plain_iterations_finish() -> None:
    nonlinear, system = solver(plain=0.9, corrected=1.5)
    report = nonlinear.solve_picard(tol=1e-4, max_iterations=500, velocity_floor=1.0)
    assert report.converged
    flags = system.flags
    first = flags.index(True)
    assert first == PRIMAL_DUAL_AFTER + 1            # after the seeding plain iteration
    assert flags[first:first + PRIMAL_DUAL_ROUND] == [True] * PRIMAL_DUAL_ROUND
    assert not any(flags[first + PRIMAL_DUAL_ROUND:])  # banned for the rest of the step
    assert nonlinear.dual.starts == 1
    # the state holds the plain increments only: the corrected ones were undone
    plain = [d for d, on in zip(_increments(system, flags), flags, strict=True) if not on]
    assert velocity_x(nonlinear) == pytest.approx(sum(plain), rel=1e-10)
    assert report.iterations == len(flags)


def test_a_converging_correction_is_confirmed_by_a_plain_iteration() -> None:
    nonlinear, system = solver(plain=0.95, corrected=0.1)
    report = nonlinear.solve_picard(tol=1e-5, max_iterations=500, velocity_floor=1.0)
    assert report.converged
    assert system.flags[-1] is False and system.flags[-2] is True
    assert report.iterations < 10                   # plain iterations alone need ~90
    assert velocity_x(nonlinear) == pytest.approx(
        sum(_increments(system, system.flags)), rel=1e-10)


def test_without_a_dual_variable_the_iteration_is_plain() -> None:
    nonlinear, system = solver(plain=0.9, corrected=1.5)
    nonlinear.dual = None
    report = nonlinear.solve_picard(tol=1e-4, max_iterations=500, velocity_floor=1.0)
    assert report.converged and not any(system.flags)
    assert report.iterations == math.ceil(math.log(0.1) / math.log(0.9))


def _increments(system: ScriptedSystem, flags: list[bool]) -> list[float]:
    d, out = 1e-3, []
    for on in flags:
        d *= system.corrected if on else system.plain
        out.append(d)
    return out
