"""The volume of revolution the axisymmetric free-surface fix conserves, and its gradient."""

from __future__ import annotations

import numpy as np
import pytest

from granflow.ale.free_surface import (
    REVOLVED,
    conserve_area,
    revolved_volume,
    revolved_volume_gradient,
)

SQUARE = np.array([[1.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0]])
RING = np.array([[0, 1], [1, 2], [2, 3], [3, 0]])


def test_a_square_section_sweeps_a_ring_of_known_volume() -> None:
    assert revolved_volume(SQUARE, RING) == pytest.approx(np.pi * (2**2 - 1**2), rel=1e-14)


def test_the_gradient_is_the_derivative_of_the_volume() -> None:
    rng = np.random.default_rng(0)
    angle = np.sort(rng.uniform(0.0, 2 * np.pi, 9))
    radius = 1.0 + 0.2 * rng.random(9)
    xy = np.column_stack([2.0 + radius * np.cos(angle), radius * np.sin(angle)])
    ring = np.array([[i, (i + 1) % 9] for i in range(9)])
    h, fd = 1e-6, np.zeros_like(xy)
    for i in range(9):
        for k in range(2):
            up, down = xy.copy(), xy.copy()
            up[i, k] += h
            down[i, k] -= h
            fd[i, k] = (revolved_volume(up, ring) - revolved_volume(down, ring)) / (2 * h)
    assert np.abs(revolved_volume_gradient(xy, ring) - fd).max() < 1e-7


def test_the_fix_restores_the_volume_not_the_area() -> None:
    xy = SQUARE.copy()
    xy[2:, 1] = 1.01                                     # the top rises by 1 %
    movable = np.array([2, 3])
    conserve_area(xy, RING, movable, np.pi * 3.0, measure=REVOLVED)
    assert revolved_volume(xy, RING) == pytest.approx(np.pi * 3.0, rel=1e-12)
