"""The well-posedness criterion of mu(I) (Barker and Gray 2017, eq. 3.9) and its window."""

import math

import numpy as np
import pytest

from granflow.diagnostics.inertial import InertialNumbers
from granflow.physics import MuI
from granflow.physics.well_posedness import (
    ill_posedness,
    smallest_ill_posedness,
    well_posed_window,
)

GLASS = {"friction_angle_deg": 20.9, "mu_2_deg": 32.76, "i0": 0.279,
         "grain_diameter": 5e-4, "grain_density": 2500.0}   # Jop et al. (2006)
PAPER = GLASS | {"friction_angle_deg": 25.5}                 # granflow's default mu_s


def law(parameters: dict) -> MuI:
    return MuI(viscosity=1.0, eps=1e-6, **parameters)


def test_criterion_against_a_finite_difference_slope() -> None:
    """C from the analytic mu'(I) equals C built from a centred difference of mu(I)."""
    m = law(GLASS)
    for i in (1e-4, 3e-3, 0.05, 0.4, 7.0):
        h = 1e-6 * i
        slope = (m.friction(i + h) - m.friction(i - h)) / (2 * h)
        nu = i * slope / m.friction(i)
        expected = 4 * nu**2 - 4 * nu + m.friction(i) ** 2 * (1 - nu / 2) ** 2
        assert ill_posedness(m, i) == pytest.approx(expected, rel=1e-7)


def test_ill_posed_at_low_and_high_inertial_numbers() -> None:
    """nu -> 0 at both ends, so C -> mu_s^2 as I -> 0 and C -> mu_2^2 as I -> infinity."""
    m = law(GLASS)
    assert ill_posedness(m, 1e-12) == pytest.approx(m.mu_s**2, rel=1e-9)
    assert ill_posedness(m, 1e9) == pytest.approx(m.mu_2**2, rel=1e-6)


def test_window_of_jop_glass_beads() -> None:
    """C vanishes at both bounds, is negative between them and positive outside."""
    m = law(GLASS)
    window = well_posed_window(m)
    assert window is not None
    low, high = window
    assert 1e-3 < low < 0.1 < high < 10.0
    for bound in window:
        assert abs(ill_posedness(m, bound)) < 1e-9
    assert ill_posedness(m, math.sqrt(low * high)) < 0
    assert ill_posedness(m, 0.9 * low) > 0 and ill_posedness(m, 1.1 * high) > 0


def test_granflow_default_friction_has_no_window() -> None:
    """With mu_s = tan 25.5 deg (the paper's) beside mu_2 = tan 32.76 deg, C > 0 at every I:
    its smallest value is small but positive, near I = 0.18."""
    m = law(PAPER)
    assert well_posed_window(m) is None
    smallest, where = smallest_ill_posedness(m)
    assert 0 < smallest < 0.01 and 0.1 < where < 0.3
    grid = np.logspace(-9, 4, 20001)                   # a finer, independent scan
    assert np.all(ill_posedness(m, grid) > 0)


def test_well_posed_fraction_of_the_recorded_inertial_numbers() -> None:
    """Weights at I = 1e-3, 0.1 and 5 against the window (0.02, 0.9): a third inside."""
    record = InertialNumbers(well_posed=(0.02, 0.9))
    record.add(np.array([1e-3, 0.1, 5.0]), np.ones(3))
    assert record.summary()["well_posed_fraction"] == pytest.approx(1 / 3)
    assert InertialNumbers().summary() is None
    record.well_posed = None
    assert record.summary()["well_posed_fraction"] == 0.0
