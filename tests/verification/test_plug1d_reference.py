"""Verification of the 1D plug-flow reference solver (Bouchut et al., section 4, (4.1)-(4.2)).

The reference must itself be trustworthy before 2D results are measured against it, hence:
self-convergence and accuracy of the defaults, an exact heat-equation solution for ``S = 0``,
and physical properties of the obstacle-problem solution (bounds, interface, smooth fit).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import trapezoid
from scipy.stats import norm

from granflow.reference import Plug1DSolution, solve_plug1d, source_term

HEIGHT = 6.0
SLOPE_DEG = 1.0
FRICTION_DEG = math.degrees(math.atan(math.tan(math.radians(SLOPE_DEG)) + 1e-2))
NU = 1.0
ALPHA1 = 1.0
B0 = 3.5
T_END = 0.2

PAPER = {
    "height": HEIGHT,
    "slope_deg": SLOPE_DEG,
    "friction_angle_deg": FRICTION_DEG,
    "kinematic_viscosity": NU,
    "shear_rate": ALPHA1,
    "plug_base": B0,
    "t_end": T_END,
}

#: required accuracy of the default discretisation at T = 0.2 s (relative L2 error in U)
DEFAULT_ACCURACY = 1e-5
#: (dz, dt) sequence of the refinement study; index 2 is the default (1e-3, 1e-4)
LEVELS = [(4e-3, 4e-4), (2e-3, 2e-4), (1e-3, 1e-4), (5e-4, 5e-5)]
FINE = (2.5e-4, 2.5e-5)


def _rel_l2(coarse: Plug1DSolution, fine: Plug1DSolution) -> float:
    """Relative L2(0, h) difference, evaluated on the coarse nodes (grids are nested)."""
    stride = (fine.z.size - 1) // (coarse.z.size - 1)
    assert np.allclose(fine.z[::stride], coarse.z)
    ref = fine.u[::stride]
    err = coarse.u - ref
    return math.sqrt(trapezoid(err**2, coarse.z) / trapezoid(ref**2, coarse.z))


def _heat_kink(z: np.ndarray, t: float, b0: float = B0, height: float = HEIGHT) -> np.ndarray:
    """Exact solution of (4.1) with S = 0: heat equation from ``ALPHA1 [Z - b0]_+``.

    On the line the kink evolves into ``x Phi(x/s) + s phi(x/s)``, ``x = Z - b0``,
    ``s = sqrt(2 nu t)``. The Neumann top is handled by the even image about ``Z = h`` (the
    extended datum is the tent ``[Z-b0]_+ - 2 [Z-h]_+ + [Z-2h+b0]_+``) and the Dirichlet bottom
    by the odd image about ``Z = 0``; further images are below 1e-30 here.
    """
    s = math.sqrt(2.0 * NU * t)

    def kink(x: np.ndarray) -> np.ndarray:
        return x * norm.cdf(x / s) + s * norm.pdf(x / s)

    def tent(zz: np.ndarray) -> np.ndarray:
        return ALPHA1 * (kink(zz - b0) - 2.0 * kink(zz - height) + kink(zz - (2 * height - b0)))

    z = np.asarray(z, dtype=float)
    return tent(z) - tent(-z)


@pytest.fixture(scope="module")
def refinement() -> list[Plug1DSolution]:
    """Paper set-up solved on the refinement levels (computed once, about 4 s)."""
    return [solve_plug1d(**PAPER, dz=dz, dt=dt) for dz, dt in LEVELS]


@pytest.fixture(scope="module")
def fine() -> Plug1DSolution:
    """Paper set-up on a grid 4x finer in space and time than the defaults (about 10 s)."""
    return solve_plug1d(**PAPER, dz=FINE[0], dt=FINE[1])


@pytest.fixture(scope="module")
def default() -> Plug1DSolution:
    """Paper set-up with the default dz, dt."""
    return solve_plug1d(**PAPER)


# --------------------------------------------------------------------------------------------
# 1. self-convergence and accuracy of the defaults
# --------------------------------------------------------------------------------------------


def test_self_convergence_order(refinement: list[Plug1DSolution]) -> None:
    """Differences between successive levels shrink at an observed order of at least 1.5."""
    dzs = np.array([dz for dz, _ in LEVELS[:-1]])
    diffs = np.array([_rel_l2(a, b) for a, b in itertools.pairwise(refinement)])
    order = np.polyfit(np.log(dzs), np.log(diffs), 1)[0]
    # measured: diffs ~ 8.0e-7, 2.3e-7, 7.1e-8 -> order ~ 1.7 (space O(dz^2); the free boundary
    # makes the time error behave like O(dt) in this regime, see the module docstring)
    assert np.all(np.diff(diffs) < 0.0), diffs
    assert order > 1.5, (order, diffs)


@pytest.mark.slow
def test_default_accuracy_against_finer_solution(
    default: Plug1DSolution, refinement: list[Plug1DSolution], fine: Plug1DSolution
) -> None:
    """Default (dz, dt) = (1e-3, 1e-4) is within 1e-5 relative L2 of a 4x finer solution."""
    assert default.z.size == refinement[2].z.size
    np.testing.assert_array_equal(default.u, refinement[2].u)  # defaults really are level 2
    err = _rel_l2(default, fine)
    # a first-order tail bound from the finer pair: |u_def - u_exact| <~ err + 2 |u_half - u_fine|
    tail = 2.0 * _rel_l2(refinement[3], fine)
    # measured: err ~ 9.6e-8, tail ~ 5.0e-8
    assert err + tail < DEFAULT_ACCURACY, (err, tail)
    assert err < 1e-6, err  # two orders of magnitude of margin, guards against regressions


def test_default_interface_converges(default: Plug1DSolution, fine: Plug1DSolution) -> None:
    """b(T) from the defaults agrees with the finer solution to 2e-4 m (measured ~1e-4 m)."""
    assert abs(default.interface - fine.interface) < 2e-4
    # and along the history at the coarse output times (after the very first instants)
    t_def, b_def = default.interface_history.T
    t_fine, b_fine = fine.interface_history.T
    for t in (0.01, 0.05, 0.1, 0.15):
        i, j = np.argmin(abs(t_def - t)), np.argmin(abs(t_fine - t))
        assert t_def[i] == pytest.approx(t_fine[j], abs=1e-12)
        assert abs(b_def[i] - b_fine[j]) < 2e-4, (t, b_def[i], b_fine[j])



# --------------------------------------------------------------------------------------------
# 2. analytic solution for S = 0 (friction angle = slope): the obstacle is never active
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("plug_base", [B0, 3.5003])  # kink on a node and between nodes
def test_zero_source_matches_heat_kink(plug_base: float) -> None:
    """With S = 0, U is the heat solution of the kinked datum (images for h and 0)."""
    params = {**PAPER, "friction_angle_deg": SLOPE_DEG, "plug_base": plug_base}
    assert source_term(slope_deg=SLOPE_DEG, friction_angle_deg=SLOPE_DEG) == 0.0
    errors = []
    for dz, dt in [(2e-3, 2e-4), (1e-3, 1e-4)]:
        sol = solve_plug1d(**params, dz=dz, dt=dt)
        exact = _heat_kink(sol.z, T_END, b0=plug_base)
        err = sol.u - exact
        errors.append(math.sqrt(trapezoid(err**2, sol.z) / trapezoid(exact**2, sol.z)))
        assert np.max(np.abs(err)) < 1e-6 * np.max(exact)
        assert np.all(sol.u[1:] > 0.0)  # the obstacle is inactive: no static layer
        assert sol.interface == 0.0
    # measured: 2.3e-7 and 5.8e-8 (clean second order)
    assert errors[1] < 1e-7, errors
    assert errors[0] / errors[1] > 3.5, errors


def test_exact_solution_has_the_expected_top_value() -> None:
    """Guard for the images: U(h) = a (2 Phi(a/s) - 1) + 2 s (phi(a/s) - phi(0)), a = h - b0."""
    s = math.sqrt(2.0 * NU * T_END)
    a = HEIGHT - B0
    expected = ALPHA1 * (a * (2 * norm.cdf(a / s) - 1) + 2 * s * (norm.pdf(a / s) - norm.pdf(0)))
    top = _heat_kink(np.array([HEIGHT]), T_END)[0]
    assert top == pytest.approx(expected, abs=1e-12)
    assert top == pytest.approx(1.9953846, abs=1e-7)
    assert _heat_kink(np.array([0.0]), T_END)[0] == 0.0


# --------------------------------------------------------------------------------------------
# 3. physics of the obstacle problem in the paper set-up
# --------------------------------------------------------------------------------------------


def test_source_term_value() -> None:
    """(4.2) with tan(delta) = tan(theta) + 1e-2: S = g cos(theta) 1e-2."""
    s_src = source_term(slope_deg=SLOPE_DEG, friction_angle_deg=FRICTION_DEG)
    assert s_src == pytest.approx(9.81 * math.cos(math.radians(SLOPE_DEG)) * 1e-2, rel=1e-12)
    assert source_term(slope_deg=10.0, friction_angle_deg=30.0, gravity=1.0) == pytest.approx(
        math.cos(math.radians(10.0)) * (math.tan(math.radians(30.0)) - math.tan(math.radians(10)))
    )


def test_interface_moves_down_first(default: Plug1DSolution) -> None:
    """Viscosity erodes the static layer: b(t) decreases from b0 (here still at T = 0.2 s)."""
    t, b = default.interface_history.T
    assert default.interface_history.shape == (t.size, 2)
    assert t[0] == 0.0
    assert b[0] == B0
    assert t[-1] == pytest.approx(T_END, abs=1e-14)
    assert np.all(np.diff(t) > 0.0)
    assert b[1] < B0
    assert np.all(np.diff(b) <= 0.0)
    # measured b(0.2) ~ 2.2095 m
    assert 2.15 < default.interface < 2.25
    assert default.interface == b[-1]


def test_solution_is_nonnegative_and_static_below_interface(default: Plug1DSolution) -> None:
    """U >= 0, U == 0 below b(T), U > 0 above it."""
    z, u, b = default.z, default.u, default.interface
    dz = z[1] - z[0]
    assert np.all(u >= 0.0)
    assert np.all(u[z < b] == 0.0)
    assert np.all(u[z > b + 2.0 * dz] > 0.0)


def test_smooth_fit_at_interface(default: Plug1DSolution) -> None:
    """(4.1b)-(4.1c): U ~ S / (2 nu) (Z - b)^2 just above b (U and U_Z vanish at b)."""
    s_src = source_term(slope_deg=SLOPE_DEG, friction_angle_deg=FRICTION_DEG)
    for d in (0.005, 0.01, 0.02):
        ratio = default(default.interface + d)[()] / (s_src / (2.0 * NU) * d * d)
        assert ratio == pytest.approx(1.0, abs=0.1), (d, ratio)


def test_comparison_bounds(default: Plug1DSolution) -> None:
    """max(U_heat - S t, 0) <= U <= U_heat (sub/supersolutions of the obstacle problem)."""
    s_src = source_term(slope_deg=SLOPE_DEG, friction_angle_deg=FRICTION_DEG)
    heat = _heat_kink(default.z, T_END)
    tol = 1e-6
    assert np.all(default.u <= heat + tol)
    assert np.all(default.u >= np.maximum(heat - s_src * T_END, 0.0) - tol)
    # far from the interface the obstacle is invisible: U(h) = U_heat(h) - S T (measured 1.9758)
    assert default.u[-1] == pytest.approx(heat[-1] - s_src * T_END, abs=1e-5)
    assert default.u.max() == default.u[-1]


def test_layer_at_rest_stays_at_rest() -> None:
    """shear_rate = 0 gives U == 0 for all time and no flowing layer (b = h)."""
    sol = solve_plug1d(**{**PAPER, "shear_rate": 0.0}, dz=4e-3, dt=4e-4)
    assert np.all(sol.u == 0.0)
    assert sol.interface == HEIGHT
    assert np.all(sol.interface_history[:, 1] == HEIGHT)


def test_grid_adapts_to_height_and_final_time() -> None:
    """dz, dt not dividing h, T: grid ends at h, last step ends at T, callable interpolates."""
    sol = solve_plug1d(**{**PAPER, "t_end": 0.0123}, dz=3.7e-3, dt=7e-4)
    assert sol.z[0] == 0.0
    assert sol.z[-1] == pytest.approx(HEIGHT, abs=1e-14)
    assert np.max(np.diff(sol.z)) <= 3.7e-3
    assert sol.t == 0.0123
    assert sol.interface_history[-1, 0] == pytest.approx(0.0123, abs=1e-14)
    zq = np.array([0.0, 4.0, 5.5, HEIGHT, 7.0])
    vals = sol(zq)
    assert vals.shape == zq.shape
    np.testing.assert_allclose(vals[:4], np.interp(zq[:4], sol.z, sol.u))
    assert vals[-1] == sol.u[-1]  # clipped to the top
    # the top is far from the obstacle: U(h) = U_heat(h) - S t, here to the accuracy of this
    # coarse grid at an early time (measured error 4e-5; 4e-7 with the defaults)
    s_src = source_term(slope_deg=SLOPE_DEG, friction_angle_deg=FRICTION_DEG)
    top = _heat_kink(np.array([HEIGHT]), 0.0123)[0] - s_src * 0.0123
    assert vals[3] == pytest.approx(top, abs=1e-4)


def test_zero_final_time_returns_initial_profile() -> None:
    """t_end = 0 returns U0 = alpha1 [Z - b0]_+ and b = b0."""
    sol = solve_plug1d(**{**PAPER, "t_end": 0.0}, dz=1e-2)
    np.testing.assert_allclose(sol.u, ALPHA1 * np.maximum(sol.z - B0, 0.0), atol=1e-15)
    assert sol.interface == B0
    assert sol.interface_history.shape == (1, 2)


@pytest.mark.parametrize(
    ("overrides", "name"),
    [
        ({"friction_angle_deg": 0.5}, "friction_angle_deg"),
        ({"height": -1.0}, "height"),
        ({"plug_base": 6.0}, "plug_base"),
        ({"plug_base": -0.1}, "plug_base"),
        ({"dz": 0.0}, "dz"),
        ({"dt": -1e-4}, "dt"),
        ({"kinematic_viscosity": 0.0}, "kinematic_viscosity"),
        ({"shear_rate": -1.0}, "shear_rate"),
        ({"t_end": -0.1}, "t_end"),
        ({"slope_deg": 90.0, "friction_angle_deg": 95.0}, "slope_deg"),
        ({"gravity": float("nan")}, "gravity"),
    ],
)
def test_invalid_input_raises(overrides: dict[str, float], name: str) -> None:
    """Inadmissible parameters raise ValueError naming the parameter."""
    with pytest.raises(ValueError, match=name):
        solve_plug1d(**{**PAPER, **overrides})
