"""The static/flowing interface: lower envelope of the flowing cells (section 5.1.2)."""

from __future__ import annotations

import numpy as np


def lower_envelope(xy: np.ndarray, tri: np.ndarray, flowing: np.ndarray,
                   stations: np.ndarray) -> np.ndarray:
    """Lowest Z of flowing triangles on each vertical X = station (NaN where none flows)."""
    result = np.full(len(stations), np.nan)
    for t in tri[flowing]:
        p = xy[t]
        x0, x1 = p[:, 0].min(), p[:, 0].max()
        inside = np.flatnonzero((stations >= x0) & (stations <= x1))
        if inside.size == 0:
            continue
        for k in inside:
            z = _vertical_cut(p, stations[k])
            if z is not None and (np.isnan(result[k]) or z < result[k]):
                result[k] = z
    return result


def _vertical_cut(p: np.ndarray, x: float) -> float | None:
    """Lowest Z where the vertical X = x meets the triangle p (3 x 2)."""
    zs = []
    for i in range(3):
        (xa, za), (xb, zb) = p[i], p[(i + 1) % 3]
        if xa == xb:
            if abs(x - xa) < 1e-15:
                zs += [za, zb]
        elif min(xa, xb) <= x <= max(xa, xb):
            zs.append(za + (zb - za) * (x - xa) / (xb - xa))
    return min(zs) if zs else None
