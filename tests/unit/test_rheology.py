"""Rung 1 of the verification ladder: the regularised Drucker–Prager law (2.4), (2.13)."""

import math

import numpy as np
import pytest

from granflow.physics import CoulombFriction, DruckerPrager


def simple_shear(rate: float) -> np.ndarray:
    """Du of u = (rate * z, 0): off-diagonal rate/2."""
    return np.array([[0.0, rate / 2], [rate / 2, 0.0]])


@pytest.mark.parametrize("rate", [-3.0, -1e-2, 1e-3, 0.5, 20.0])
def test_simple_shear_stress_tends_to_bingham_drucker_prager(rate: float) -> None:
    """sigma'_xz -> eta U' + mu_s p sign(U') as eps -> 0 (no 1/2 in the Frobenius norm)."""
    eta, p, delta = 2.0, 1500.0, 25.5
    mu_s = math.tan(math.radians(delta))
    exact = eta * rate + mu_s * p * math.copysign(1.0, rate)
    errors = []
    for eps in [1e-2, 1e-4, 1e-6, 1e-8]:
        law = DruckerPrager(viscosity=eta, friction_angle_deg=delta, eps=eps)
        stress = law.deviatoric_stress(simple_shear(rate), p)
        errors.append(abs(stress[0, 1] - exact) / abs(exact))
    assert errors[-1] < 1e-9
    assert all(b <= a for a, b in zip(errors, errors[1:], strict=False))


def test_effective_viscosity_is_finite_at_rest() -> None:
    law = DruckerPrager(viscosity=1.0, friction_angle_deg=25.5, eps=1e-6)
    value = law.effective_viscosity(0.0, 1000.0)
    assert math.isfinite(value)
    assert value == pytest.approx(2.0 + math.sqrt(2) * law.mu_s * 1000.0 / 1e-6)


def test_yield_stress_vanishes_for_tension() -> None:
    law = DruckerPrager(viscosity=1.0, friction_angle_deg=30.0, eps=1e-6)
    assert law.yield_stress(-5.0) == 0.0
    assert law.yield_stress(np.array([2.0]))[0] == pytest.approx(math.sqrt(2) * law.mu_s * 2.0)


def test_deviatoric_stress_norm_reaches_yield_stress() -> None:
    """|sigma'| -> 2 eta |Du| + kappa: the plastic part has the norm of kappa."""
    law = DruckerPrager(viscosity=0.0, friction_angle_deg=25.5, eps=1e-9)
    d = np.array([[0.3, 0.1], [0.1, -0.3]])
    stress = law.deviatoric_stress(d, 800.0)
    assert np.linalg.norm(stress) == pytest.approx(law.yield_stress(800.0), rel=1e-9)


def test_invalid_parameters_are_refused() -> None:
    with pytest.raises(ValueError, match="eps"):
        DruckerPrager(viscosity=1.0, friction_angle_deg=20.0, eps=0.0)
    with pytest.raises(ValueError, match="friction_angle_deg"):
        CoulombFriction(friction_angle_deg=95.0, eps_friction=1e-6)


def test_friction_drag_gives_coulomb_traction() -> None:
    """|traction| = drag * |u_T| -> mu [p - sigma'_N]_+ for slip >> eps_f, 0 when unloaded."""
    law = CoulombFriction(friction_angle_deg=25.5, eps_friction=1e-6)
    slip, load = 0.3, 1200.0
    traction = law.drag_coefficient(slip, load) * slip
    assert traction == pytest.approx(law.mu * load, rel=1e-9)
    assert law.drag_coefficient(slip, -10.0) == 0.0
