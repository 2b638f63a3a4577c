"""Front position, height at the wall, stopping times (sections 5.1.2, 5.3.1)."""

from __future__ import annotations

import numpy as np

from granflow.geometry.profile import Line


def front_position(xy: np.ndarray) -> float:
    """Runout: the largest X of the mass."""
    return float(xy[:, 0].max())


def wall_height(xy: np.ndarray, wall: Line | None, tol: float = 1e-12) -> float:
    """Height of the mass along the left wall (``diagnostics.csv: wall_height``, the
    summary's ``wall_height_m``): the farthest of the points on the wall from its foot,
    measured along it (on the paper's bed, the largest Z at X = 0); 0 without a wall."""
    if wall is None:
        return 0.0
    on_wall = wall.height(xy) <= tol
    return float(wall.along(xy[on_wall]).max()) if np.any(on_wall) else 0.0


def stop_time(t: np.ndarray, flowing_fraction: np.ndarray,
              fraction: float = 0.0) -> float | None:
    """Time from which the flowing cells hold at most ``fraction`` of the area to the end
    of the record, after the onset of motion; with ``fraction`` 0, every cell is static.

    None if the mass never moved or still flows at the end.
    """
    flowing = np.flatnonzero(np.asarray(flowing_fraction) > fraction)
    if flowing.size == 0 or flowing[-1] == len(t) - 1:
        return None
    return float(t[flowing[-1] + 1])


def front_stop_time(t: np.ndarray, front_speed: np.ndarray,
                    threshold: float = 1e-3) -> float | None:
    """First time after which the material at the front stays slower than ``threshold``.

    None if the front never moved faster, or still does at the end.
    """
    fast = np.flatnonzero(np.asarray(front_speed) > threshold)
    if fast.size == 0 or fast[-1] == len(t) - 1:
        return None
    return float(t[fast[-1] + 1])


def thick_front(surface: np.ndarray, thickness: float = 1e-3) -> float:
    """Largest X where the free surface (x, z polyline) stands at least ``thickness`` above
    the bed: a runout that ignores the micrometre-thin tongue a regularised front leaves."""
    thick = surface[:, 1] >= thickness
    return float(surface[thick, 0].max()) if np.any(thick) else 0.0


def surface_edge_spread(surface: np.ndarray) -> float:
    """Longest over shortest free-surface edge: how evenly the ALE keeps the surface nodes."""
    lengths = np.linalg.norm(np.diff(surface, axis=0), axis=1)
    return float(lengths.max() / lengths.min()) if lengths.min() > 0 else float("inf")


def settle_time(t: np.ndarray, front_x: np.ndarray, tol: float = 1e-3) -> float | None:
    """First time after which the front stays within ``tol`` of its final position.

    Less sensitive to the mesh than ``front_stop_time``, which looks at the speed of the
    few cells at the tip. None if the front never moved by more than ``tol``.
    """
    front_x = np.asarray(front_x)
    away = np.flatnonzero(np.abs(front_x - front_x[-1]) > tol) if front_x.size else []
    if len(away) == 0 or away[-1] + 1 == len(t):
        return None
    return float(t[away[-1] + 1])


def flow_duration(t: np.ndarray, flowing_fraction: np.ndarray,
                  fraction: float = 0.01) -> float | None:
    """When the flow ends: the first time after the flowing area's peak at which less than
    ``fraction`` of the domain flows. Less fragile than the rest rule's stop time, which a
    thin front creeping about its 0.1 % threshold can delay by tenths of a second. None if
    the mass never moved or still flows at the end."""
    flowing = np.asarray(flowing_fraction, dtype=float)
    if not len(flowing) or flowing.max() <= 0:
        return None
    peak = int(flowing.argmax())
    after = flowing[peak:] < fraction
    return float(np.asarray(t)[peak + int(after.argmax())]) if after.any() else None
