"""The mu(I) law (physics/mu_i.py) and the side-wall drag: simple shear, limits, errors."""

import math

import numpy as np
import pytest

from granflow.physics import MuI, SideWallFriction
from granflow.reference.incline import bagnold_profile, mu_i_profile

GLASS = {"friction_angle_deg": 20.9, "mu_2_deg": 32.76, "i0": 0.279,
         "grain_diameter": 5e-4, "grain_density": 2500.0}


@pytest.mark.parametrize("rate", [0.3, 5.0, 80.0])
@pytest.mark.parametrize("pressure", [10.0, 500.0])
def test_simple_shear_stress_is_eta_rate_plus_mu_of_i_times_p(rate: float,
                                                              pressure: float) -> None:
    """u = (rate z, 0): |Du| = rate / sqrt(2), gamma_dot = rate, and sigma'_xz = m Du_xz must
    be eta rate + mu(I) p with I = rate d / sqrt(p / rho_s) (Jop et al. 2006)."""
    law = MuI(viscosity=0.01, eps=1e-9, **GLASS)
    inertial = rate * 5e-4 / math.sqrt(pressure / 2500.0)
    mu = law.mu_s + (law.mu_2 - law.mu_s) * inertial / (0.279 + inertial)
    m = law.effective_viscosity(rate / math.sqrt(2.0), pressure)
    assert m * rate / 2 == pytest.approx(0.01 * rate + mu * pressure, rel=1e-9)
    assert law.inertial_number(rate, pressure) == pytest.approx(inertial, rel=1e-9)


def test_limits_at_rest_and_at_the_surface() -> None:
    law = MuI(viscosity=1.0, eps=1e-6, **GLASS)
    # at rest the yield stress is the Drucker-Prager one, sqrt(2) mu_s p (I -> 0)
    assert law.yield_stress_sq(0.0, 1000.0) == pytest.approx(
        math.sqrt(2) * law.mu_s * 1000.0, rel=1e-6)
    # no pressure, no friction: only the viscosity is left, and no NaN
    assert law.effective_viscosity(3.0, 0.0) == pytest.approx(2.0)
    assert law.effective_viscosity(3.0, -50.0) == pytest.approx(2.0)
    assert np.isfinite(law.effective_viscosity_sq(0.0, 0.0))


def test_inverse_friction_and_range() -> None:
    law = MuI(viscosity=1.0, eps=1e-6, **GLASS)
    i = law.inverse_friction(math.tan(math.radians(25)))
    assert law.friction(i) == pytest.approx(math.tan(math.radians(25)))
    with pytest.raises(ValueError, match="mu"):
        law.inverse_friction(law.mu_2 + 0.01)
    with pytest.raises(ValueError, match="mu_2 angle"):
        MuI(viscosity=1.0, eps=1e-6, **(GLASS | {"mu_2_deg": 20.0}))
    with pytest.raises(ValueError, match="grain_diameter"):
        MuI(viscosity=1.0, eps=1e-6, **(GLASS | {"grain_diameter": 0.0}))


def test_steady_profile_tends_to_bagnold_without_viscosity() -> None:
    """The depth-by-depth root of reference/incline.py against the closed form (eta = 0):
    two independent ways to the same profile; with eta the surface speed drops."""
    law = MuI(viscosity=0.0, eps=1e-6, **GLASS)
    for slope in (23.0, 27.0):
        exact = bagnold_profile(height=0.01, slope_deg=slope, law=law, density=1500.0)
        root = mu_i_profile(height=0.01, slope_deg=slope, law=law, density=1500.0)
        assert np.max(np.abs(root.u - exact.u)) < 1e-6 * exact.u[-1]
    viscous = mu_i_profile(height=0.01, slope_deg=23.0,
                           law=MuI(viscosity=1e-2, eps=1e-6, **GLASS), density=1500.0)
    inviscid = bagnold_profile(height=0.01, slope_deg=23.0, law=law, density=1500.0)
    assert viscous.u[-1] < 0.99 * inviscid.u[-1]


def test_side_wall_drag() -> None:
    walls = SideWallFriction(channel_width=0.1, friction_angle_deg=10.2, eps_friction=1e-9)
    mu_w = math.tan(math.radians(10.2))
    # |u| = 0.5: drag coefficient c, force c |u| = 2 mu_w p / W
    assert walls.drag_coefficient_sq(0.25, 300.0) * 0.5 == pytest.approx(2 * mu_w * 300.0 / 0.1)
    assert walls.drag_coefficient_sq(0.25, -1.0) == 0.0
    with pytest.raises(ValueError, match="channel_width"):
        SideWallFriction(channel_width=0.0, friction_angle_deg=10.0, eps_friction=1e-6)
