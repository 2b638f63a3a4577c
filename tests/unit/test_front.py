"""Front diagnostics of the collapse: stop times, thick front, surface node spread."""

import numpy as np
import pytest

from granflow.diagnostics.front import (
    front_stop_time,
    settle_time,
    stop_time,
    surface_edge_spread,
    thick_front,
    wall_height,
)
from granflow.geometry.profile import Line


def test_stop_time_is_where_the_mass_stays_static_to_the_end() -> None:
    t = np.arange(6) * 0.1
    flowing = np.array([0, 0.5, 0.4, 0.0, 0.1, 0.0])
    assert stop_time(t, flowing) == pytest.approx(0.5)              # it moved again at 0.4
    assert stop_time(t, np.zeros(6)) is None                         # never moved
    assert stop_time(t, np.array([0, 1, 1, 1, 1, 1.0])) is None      # still flowing


def test_stop_time_with_a_creeping_fraction() -> None:
    """A tip holding 0.05 % of the area above the threshold does not keep the mass moving
    when the rule allows 0.1 %."""
    t = np.arange(6) * 0.1
    flowing = np.array([0, 0.5, 0.2, 5e-4, 5e-4, 5e-4])
    assert stop_time(t, flowing) is None
    assert stop_time(t, flowing, fraction=1e-3) == pytest.approx(0.3)


def test_front_stop_time_ignores_a_front_that_still_moves_at_the_end() -> None:
    t = np.arange(5) * 0.1
    assert front_stop_time(t, np.array([0.1, 0.1, 5e-4, 2e-3, 1e-4])) == pytest.approx(0.4)
    assert front_stop_time(t, np.array([0.1, 0.1, 0.1, 0.1, 0.1])) is None


def test_thick_front_skips_the_micrometre_tongue() -> None:
    surface = np.array([[0.0, 0.2], [0.3, 0.05], [0.45, 2e-3], [0.5, 5e-4], [0.6, 0.0]])
    assert thick_front(surface) == pytest.approx(0.45)
    assert thick_front(surface, thickness=1e-4) == pytest.approx(0.5)


def test_surface_edge_spread_is_longest_over_shortest_edge() -> None:
    surface = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.25], [3.0, 0.25]])
    assert surface_edge_spread(surface) == pytest.approx(8.0)


def test_settle_time_is_when_the_front_comes_within_tolerance_of_its_final_position() -> None:
    t = np.arange(6) * 0.1
    front = np.array([0.30, 0.40, 0.448, 0.4497, 0.4502, 0.4505])
    assert settle_time(t, front) == pytest.approx(0.3)
    assert settle_time(t, np.full(6, 0.3)) is None


def test_the_wall_height_is_measured_along_the_wall() -> None:
    """On the paper's bed the wall is X = 0 and the height the largest Z on it; on a bed
    tilted by 30 degrees the wall stands normal to the bed and the height runs along it."""
    upright = Line.through(np.zeros(2), np.array([0.0, 1.0]), np.array([1.0, 0.0]))
    mass = np.array([[0.0, 0.0], [0.0, 0.14], [0.2, 0.1], [0.1, 0.2]])
    assert wall_height(mass, upright) == pytest.approx(0.14)
    assert wall_height(mass, None) == 0.0
    assert wall_height(mass + [0.01, 0.0], upright) == 0.0       # nothing on the wall
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    tilted = Line.through(np.zeros(2), np.array([s, c]), np.array([c, -s]))
    on_it = np.array([[0.0, 0.0], [0.1 * s, 0.1 * c], [0.2 * c, -0.2 * s]])
    assert wall_height(on_it, tilted) == pytest.approx(0.1)
