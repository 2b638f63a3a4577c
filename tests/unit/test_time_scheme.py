"""The time schemes against an analytic solution: the inertia term, history and predictor of
``fem/time_scheme.py`` integrate rho du/dt = -k rho u (u(0) = u0 uniform) on a finite
element space; u(t) = u0 exp(-k t). Observed orders: 1 for implicit Euler, 2 for BDF2,
with constant and with smoothly varying steps."""

import math

import ngsolve as ngs
import numpy as np
import pytest
from netgen.geom2d import unit_square

from granflow.fem.forms import Symbols
from granflow.fem.spaces import taylor_hood
from granflow.fem.time_scheme import bdf2_coefficients, milne_factor, time_scheme

K = 3.0       # decay rate, 1/s
T_END = 1.0


def _integrate(name: str, n_steps: int, varying: bool) -> tuple[float, list[float]]:
    """Final value error |u_h(T) - u(T)| and the ratios (local error estimate / true local
    error) of the steps that had an estimate."""
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.5))
    space = taylor_hood(mesh, periodic=False, dirichlet="")
    scheme = time_scheme(name, space, density=2.0)
    (u, p), (v, q) = space.TnT()
    s = Symbols(u=u, p=p, v=v, q=q, u_lin=u, p_lin=p)
    inertia = scheme.inertia()
    lhs = ngs.BilinearForm(space)
    lhs += inertia.lhs(s, mesh) + K * scheme.density * u * v * ngs.dx + p * q * ngs.dx
    rhs = ngs.LinearForm(space)
    rhs += inertia.rhs(s, mesh)
    solution = ngs.GridFunction(space)
    predictor = ngs.GridFunction(space)
    scheme.previous.components[0].Set((1.0, -0.5))
    scheme.set_initial()
    # constant steps, or steps growing smoothly by a factor 3 over the run (as the step
    # controller changes them), summing to T_END
    weights = [1.0 + 2.0 * i / n_steps if varying else 1.0 for i in range(n_steps)]
    steps = [T_END * w / sum(weights) for w in weights]
    t, ratios = 0.0, []
    for dt in steps:
        scheme.begin_step(dt)
        lhs.Assemble()
        rhs.Assemble()
        solution.vec.data = lhs.mat.Inverse(space.FreeDofs(), inverse="umfpack") * rhs.vec
        factor = scheme.error_predictor(dt, predictor)
        u_n = scheme.previous.components[0].vec.FV().NumPy()[0]
        u_new = solution.components[0].vec.FV().NumPy()[0]
        if factor is not None:
            estimate = factor * (u_new - predictor.components[0].vec.FV().NumPy()[0])
            exact_local = u_new - u_n * math.exp(-K * dt)
            ratios.append(estimate / exact_local)
        scheme.accept(solution, dt)
        t += dt
    exact = math.exp(-K * t)
    return abs(scheme.previous.components[0].vec.FV().NumPy()[0] - exact), ratios


@pytest.mark.parametrize(("name", "order"), [("implicit-euler", 1), ("bdf2", 2)])
@pytest.mark.parametrize("varying", [False, True])
def test_observed_order(name: str, order: int, varying: bool) -> None:
    errors = [_integrate(name, n, varying)[0] for n in (40, 80, 160)]
    observed = [math.log2(a / b) for a, b in zip(errors[:-1], errors[1:], strict=True)]
    assert observed == pytest.approx([order, order], abs=0.1), (errors, observed)


@pytest.mark.parametrize(("name", "share"), [("implicit-euler", 2 / 3), ("bdf2", 1.0)])
def test_error_estimate_tracks_the_error_each_step_adds(name: str, share: float) -> None:
    """The Milne estimate is the error each step adds to the solution (u^{n+1} minus the
    exact flow of u^n over the step) to leading order: within 5 % on a smooth solution at
    160 steps after a start-up of ten, also when the steps grow smoothly by a factor 3.
    Implicit Euler's estimate keeps the factor of its verified results, 2/3 of that error
    (``fem/time_scheme.py``)."""
    for varying in (False, True):
        ratios = _integrate(name, 160, varying)[1]
        assert np.allclose(ratios[10:], share, rtol=0.05), (varying, ratios[:8])


def test_bdf2_coefficients_and_milne_constants() -> None:
    """Constant steps: (3/2, 2, 1/2); Milne's factor 1/2 for implicit Euler against a linear
    predictor (a step adds h^2/2 u'', the predictor misses by h^2 u'') and 1/3 for BDF2
    (a step adds h^3/3 u''', the predictor misses by h^3 u''')."""
    assert bdf2_coefficients(0.1, 0.1) == pytest.approx((1.5, 2.0, 0.5))
    assert milne_factor(1, 0.1, (0.1,)) == pytest.approx(1 / 2)
    assert milne_factor(2, 0.1, (0.1, 0.1)) == pytest.approx(1 / 3)
