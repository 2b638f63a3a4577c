"""Distances between two polylines (two runs' free surfaces), for convergence and A/B checks."""

from __future__ import annotations

import numpy as np


def point_to_polyline(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """Distance from each point (n, 2) to the nearest point of the polyline (m, 2)."""
    a, b = polyline[:-1], polyline[1:]
    d = b - a
    length2 = np.maximum(np.sum(d * d, axis=1), 1e-300)
    rel = points[:, None, :] - a[None, :, :]
    s = np.clip(np.sum(rel * d[None], axis=2) / length2[None], 0.0, 1.0)
    nearest = a[None] + s[..., None] * d[None]
    return np.sqrt(np.min(np.sum((points[:, None, :] - nearest) ** 2, axis=2), axis=1))


def surface_distance(first: np.ndarray, second: np.ndarray) -> tuple[float, float]:
    """(mean, max) of the symmetric point-to-polyline distances between two surfaces.

    Every vertex of each polyline is measured against the other one, so a bump that only
    one of them has counts, whichever it is.
    """
    d = np.concatenate([point_to_polyline(first, second), point_to_polyline(second, first)])
    return float(d.mean()), float(d.max())
