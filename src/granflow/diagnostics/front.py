"""Front position, height at the wall, stopping times (sections 5.1.2, 5.3.1)."""

from __future__ import annotations

import numpy as np


def front_position(xy: np.ndarray) -> float:
    """Runout: the largest X of the mass."""
    return float(xy[:, 0].max())


def wall_height(xy: np.ndarray, tol: float = 1e-12) -> float:
    """Height of the mass at the wall X = 0."""
    on_wall = xy[:, 0] <= tol
    return float(xy[on_wall, 1].max()) if np.any(on_wall) else 0.0


def stop_time(t: np.ndarray, flowing_fraction: np.ndarray) -> float | None:
    """First time after the onset of motion at which every cell is static."""
    moving = np.flatnonzero(flowing_fraction > 0)
    if moving.size == 0:
        return None
    after = np.flatnonzero((np.arange(len(t)) > moving[0]) & (flowing_fraction == 0))
    return float(t[after[0]]) if after.size else None


def front_stop_time(t: np.ndarray, front_x: np.ndarray, tol: float = 1e-4) -> float | None:
    """First time after which the front advances by less than ``tol`` metres."""
    if len(t) == 0:
        return None
    ahead = np.maximum.accumulate(front_x[::-1])[::-1]   # max of the future, inclusive
    still = np.flatnonzero(ahead - front_x < tol)
    moved = np.flatnonzero(front_x - front_x[0] > tol)
    if moved.size == 0:
        return None
    still = still[still >= moved[0]]
    return float(t[still[0]]) if still.size and still[0] < len(t) - 1 else None
