"""The nonlocal fluidity law (physics/nonlocal_fluidity.py), its 1D incline reference
(reference/nonlocal_incline.py), the beads' fit (reference/beads.py) and its configuration."""

from __future__ import annotations

import math

import numpy as np
import pytest

from granflow.config import ConfigError, load_config
from granflow.physics import DruckerPrager
from granflow.physics.nonlocal_fluidity import NonlocalFluidity
from granflow.reference import beads
from granflow.reference.incline import bagnold
from granflow.reference.nonlocal_incline import steady_nonlocal_flow

BEADS = dict(viscosity=0.0, friction_angle_deg=20.9, b=0.9377, amplitude=0.48,
             grain_diameter=0.53e-3, grain_density=2500.0, eps=1e-6)


def law(**changes) -> NonlocalFluidity:
    return NonlocalFluidity(**(BEADS | changes))


def stress_ratio(m: float, shear_rate: float, pressure: float) -> float:
    """|sigma'| / (sqrt(2) P) in simple shear: sigma'_xz = m u' / 2, gamma_dot = u'."""
    return m * shear_rate / 2 / pressure


def test_homogeneous_steady_state_is_the_linear_local_law() -> None:
    """At g = gamma_dot / (mu_s + b I) the flow rule gives the stress ratio mu_s + b I."""
    pressure, rate = 150.0, 12.0
    beads_ = law()
    inertial = beads_.inertial_number(rate, pressure)
    g = rate / beads_.local_friction(inertial)
    m = law(fluidity=g).effective_viscosity_sq((rate / math.sqrt(2)) ** 2, pressure)
    assert stress_ratio(m, rate, pressure) == pytest.approx(beads_.mu_s + beads_.b * inertial,
                                                            rel=1e-6)
    assert beads_.local_fluidity(beads_.local_friction(inertial), pressure) == pytest.approx(
        g, rel=1e-9)


def test_rest_state_has_the_regularised_drucker_prager_viscosity() -> None:
    """g = 0: m = 2 P / g_eps = sqrt(2) mu_s P / eps, (2.13) at Du = 0."""
    dp = DruckerPrager(viscosity=0.0, friction_angle_deg=20.9, eps=1e-6)
    assert law().effective_viscosity_sq(0.0, 80.0) == pytest.approx(
        dp.effective_viscosity_sq(0.0, 80.0), rel=1e-12)


def test_stress_ratio_of_material_at_rest_is_capped() -> None:
    """With the cap at mu_2 the stress ratio never exceeds tan(mu_2); without it, it grows
    with the rate."""
    pressure = 100.0
    for rate in (1e-3, 1.0, 1e3):
        capped = law(friction_cap_deg=32.76).effective_viscosity_sq((rate / math.sqrt(2)) ** 2,
                                                                    pressure)
        assert stress_ratio(capped, rate, pressure) <= math.tan(math.radians(32.76)) * (1 + 1e-9)
    free = law().effective_viscosity_sq((1e3 / math.sqrt(2)) ** 2, pressure)
    assert stress_ratio(free, 1e3, pressure) > 1e6


def test_flowing_material_below_the_cap_is_unchanged_by_it() -> None:
    pressure, rate = 150.0, 12.0
    g = rate / law().local_friction(law().inertial_number(rate, pressure))
    shear_sq = (rate / math.sqrt(2)) ** 2
    assert law(fluidity=g, friction_cap_deg=32.76).effective_viscosity_sq(
        shear_sq, pressure) == law(fluidity=g).effective_viscosity_sq(shear_sq, pressure)


@pytest.mark.parametrize(("slope", "expected_mm"), [(22.0, 2.68), (25.5, 1.30)])
def test_stopping_height_of_the_beads(slope: float, expected_mm: float) -> None:
    """(pi / 2) A d / sqrt(tan(theta) - mu_s), d = 0.53 mm."""
    assert law().stopping_height(slope) * 1e3 == pytest.approx(expected_mm, abs=0.01)
    assert law().stopping_height(20.0) == math.inf


@pytest.mark.parametrize(("slope", "expected_mm"), [(22.0, 9.45), (25.5, 1.53)])
def test_beads_fit_stopping_height(slope: float, expected_mm: float) -> None:
    assert beads.stopping_height(slope, 0.53e-3) * 1e3 == pytest.approx(expected_mm, abs=0.01)
    assert beads.froude(0.02, slope, 0.53e-3) == pytest.approx(
        0.136 * 0.02 / beads.stopping_height(slope, 0.53e-3))


@pytest.mark.parametrize("slope", [22.0, 26.0, 30.0])
def test_1d_steady_flow_exists_exactly_above_the_stopping_height(slope: float) -> None:
    h_stop = law().stopping_height(slope)
    below = steady_nonlocal_flow(law=law(), height=0.98 * h_stop, slope_deg=slope,
                                 density=1500.0)
    above = steady_nonlocal_flow(law=law(), height=1.02 * h_stop, slope_deg=slope,
                                 density=1500.0)
    assert not below.flowing and below.mean_velocity == 0.0
    assert above.flowing and above.mean_velocity > 0.0


def test_1d_local_limit_is_bagnolds_profile() -> None:
    local = law(amplitude=0.0)
    flow = steady_nonlocal_flow(law=local, height=0.01, slope_deg=24.0, density=1500.0)
    exact = bagnold(height=0.01, slope_deg=24.0,
                    inertial_number=local.local_inertial_number(math.tan(math.radians(24.0))),
                    grain_diameter=0.53e-3, packing=0.6)
    ref = exact(flow.z)
    assert np.max(np.abs(flow.u - ref)) / ref.max() < 1e-4


@pytest.mark.parametrize(("overrides", "message"), [
    (["material.friction=hysteretic"], "cannot be combined"),
    (["material.friction_angle_deg=0"], "must be > 0"),
    (["material.grain_density=1000"], "packing fraction"),
])
def test_nonlocal_refusals(overrides: list[str], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        load_config("incline-mu-i", ["material.rheology=nonlocal", *overrides])


def test_a_nonlocal_column_over_a_local_layer_is_refused() -> None:
    with pytest.raises(ConfigError, match="follows the nonlocal law needs the other one to "
                                          "follow it too"):
        load_config("trapezoid-erodible", ["material.rheology=nonlocal",
                                           "layer.rheology=drucker-prager"])


@pytest.mark.parametrize("key", ["material.nonlocal_b=0.5", "initial.fluidity=1",
                                 "numerics.fluidity_coupling=iterated"])
def test_nonlocal_keys_without_the_law_are_inert(key: str) -> None:
    with pytest.raises(ConfigError, match="no effect"):
        load_config("incline-mu-i", [key])
