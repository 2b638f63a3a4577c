"""The bed as a polyline z_b(x) and the straight walls of a domain (the left wall, the far
end of an erodible layer, a gate): where boundary nodes are kept, and when a moving node
reaches them (section 3.3, Figure 2).

The bed's first and last segments go on as rays, so a node can always be put back on it.
A segment or wall that is level or vertical is handled exactly (a node's other coordinate
is left as it is, the bed's height is written as it is): on the flat bed z = 0 of the
built-in columns, projecting and landing are the plain z = 0 and x = 0 of the paper.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

CORNER_DEG = 1e-6   # the bed turns by more than this at a corner (degrees)
REACHED = 1e-12     # m: a node this close below a segment's line is on it (it lands now)


@dataclass(frozen=True)
class Line:
    """A straight wall: through ``point``, along the unit ``direction``; ``inner`` is the
    unit normal pointing into the material (a node with a negative height has crossed)."""

    point: tuple[float, float]
    direction: tuple[float, float]
    inner: tuple[float, float]

    @classmethod
    def through(cls, point: np.ndarray, direction: np.ndarray, inside: np.ndarray) -> Line:
        """The line through ``point`` along ``direction``, with the material on the side of
        the point ``inside``. A direction within round-off of an axis is that axis."""
        t = np.asarray(direction, dtype=float) / np.hypot(*direction)
        t = np.where(np.abs(t) < 1e-15, 0.0, t)
        t = t / np.hypot(*t)
        n = np.array([-t[1], t[0]])
        if float(np.dot(np.asarray(inside, float) - point, n)) < 0:
            n = -n
        return cls((float(point[0]), float(point[1])), (float(t[0]), float(t[1])),
                   (float(n[0]) + 0.0, float(n[1]) + 0.0))

    def height(self, xy: np.ndarray) -> np.ndarray:
        """Signed distance of the points from the line, positive on the material's side."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)
        n = self.inner
        if n[1] == 0.0:                       # a vertical wall: the x distance, exactly
            return (p[:, 0] - self.point[0]) * n[0]
        if n[0] == 0.0:                       # a level one
            return (p[:, 1] - self.point[1]) * n[1]
        return (p[:, 0] - self.point[0]) * n[0] + (p[:, 1] - self.point[1]) * n[1]

    def project(self, xy: np.ndarray) -> np.ndarray:
        """The points moved normally onto the line (a copy)."""
        out = np.array(xy, dtype=float, copy=True).reshape(-1, 2)
        if self.inner[1] == 0.0:
            out[:, 0] = self.point[0]
        elif self.inner[0] == 0.0:
            out[:, 1] = self.point[1]
        else:
            out -= self.height(out)[:, None] * np.asarray(self.inner)
        return out

    def landing_time(self, xy: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        """Time for each point moving at ``velocity`` to reach the line (inf if never)."""
        v = _dot(np.asarray(velocity, dtype=float), self.inner)
        h = self.height(xy)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(v < 0, h / -v, np.inf)

    def along(self, xy: np.ndarray) -> np.ndarray:
        """Distance of the points' feet from ``point`` along ``direction``."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2) - self.point
        return _dot(p, self.direction)

    def at(self, s: float) -> np.ndarray:
        return np.asarray(self.point) + s * np.asarray(self.direction)

    def meets(self, other: Line) -> np.ndarray:
        """Where two lines cross."""
        a, t, b, u = (np.asarray(v) for v in (self.point, self.direction, other.point,
                                               other.direction))
        det = t[0] * -u[1] + u[0] * t[1]
        s = ((b - a)[0] * -u[1] + u[0] * (b - a)[1]) / det
        return a + s * t


@dataclass(frozen=True)
class BedProfile:
    """The rigid bed z_b(x): a polyline with x increasing, its ends continued as rays."""

    points: np.ndarray                               # (n, 2), n >= 2
    _start: np.ndarray = field(init=False, repr=False)
    _tangent: np.ndarray = field(init=False, repr=False)
    _normal: np.ndarray = field(init=False, repr=False)
    _length: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float).reshape(-1, 2)
        if len(pts) < 2 or np.any(np.diff(pts[:, 0]) <= 0):
            raise ValueError("a bed profile needs at least two points with x increasing")
        d = np.diff(pts, axis=0)
        length = np.hypot(d[:, 0], d[:, 1])
        t = d / length[:, None]
        t[d[:, 1] == 0] = (1.0, 0.0)          # level segments: exactly
        object.__setattr__(self, "points", pts)
        object.__setattr__(self, "_start", pts[:-1])
        object.__setattr__(self, "_tangent", t)
        object.__setattr__(self, "_normal", np.column_stack([-t[:, 1], t[:, 0]]) + 0.0)
        object.__setattr__(self, "_length", length)

    @classmethod
    def flat(cls, x0: float = 0.0, x1: float = 1.0, z: float = 0.0) -> BedProfile:
        return cls(np.array([[x0, z], [x1, z]]))

    @property
    def level(self) -> bool:
        """One level line z = z_0 (the built-in columns' bed when z_0 = 0)."""
        return bool(np.all(self.points[:, 1] == self.points[0, 1]))

    @property
    def segments(self) -> int:
        return len(self.points) - 1

    def z(self, x: np.ndarray | float) -> np.ndarray:
        """z_b(x), the end segments continued."""
        xs = np.atleast_1d(np.asarray(x, dtype=float))
        k = self.segment_of(xs)
        a, t = self._start[k], self._tangent[k]
        return a[:, 1] + (xs - a[:, 0]) * t[:, 1] / t[:, 0]

    def slope_deg(self, k: int | np.ndarray) -> np.ndarray:
        """Inclination of segment k (positive rising with x)."""
        t = self._tangent[k]
        return np.degrees(np.arctan2(t[..., 1], t[..., 0]))

    def segment_of(self, x: np.ndarray) -> np.ndarray:
        """Index of the segment above which each x lies (end segments beyond the ends)."""
        k = np.searchsorted(self.points[:, 0], np.asarray(x, dtype=float), side="right") - 1
        return np.clip(k, 0, self.segments - 1)

    def normal(self, k: int) -> np.ndarray:
        """Unit normal of segment k, pointing up."""
        return self._normal[k].copy()

    def tangent(self, k: int) -> np.ndarray:
        return self._tangent[k].copy()

    def corners(self) -> np.ndarray:
        """The inner points where the bed turns (by more than CORNER_DEG)."""
        t = self._tangent
        turn = np.degrees(np.abs(np.arctan2(t[:-1, 0] * t[1:, 1] - t[:-1, 1] * t[1:, 0],
                                            np.sum(t[:-1] * t[1:], axis=1))))
        return self.points[1:-1][turn > CORNER_DEG]

    # --- nodes and the bed ------------------------------------------------------------
    def _feet(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For every point and segment: the foot on the segment (clamped to it, rays at the
        ends), its distance, and whether it is inside the segment (not at an end point)."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)[:, None, :]
        a, t, n = self._start[None], self._tangent[None], self._normal[None]
        rel = p - a
        s = rel[..., 0] * t[..., 0] + rel[..., 1] * t[..., 1]
        lo = np.full(self.segments, 0.0)
        hi = self._length.copy()
        lo[0], hi[-1] = -np.inf, np.inf
        inside = (s >= lo) & (s <= hi)
        h = rel[..., 0] * n[..., 0] + rel[..., 1] * n[..., 1]
        level = (t[..., 1] == 0.0) & inside
        foot = np.where(inside[..., None], p - h[..., None] * n,
                        a + np.clip(s, lo, hi)[..., None] * t)
        foot[..., 0] = np.where(level, p[..., 0], foot[..., 0])   # exact on a level bed
        foot[..., 1] = np.where(level, a[..., 1], foot[..., 1])
        dist = np.where(inside, np.abs(h), np.hypot(*(p - foot).transpose(2, 0, 1)))
        return foot, dist, inside

    def project(self, xy: np.ndarray) -> np.ndarray:
        """The nearest point of the bed to each point: a node slides along the bed and
        through its corners onto the next segment."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)
        if not len(p):
            return p.copy()
        foot, dist, _ = self._feet(p)
        k = np.argmin(dist, axis=1)
        return foot[np.arange(len(p)), k]

    def height(self, xy: np.ndarray) -> np.ndarray:
        """Signed distance of each point from the bed, positive above it."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)
        if not len(p):
            return np.zeros(0)
        if self.segments == 1:                 # one line: its signed distance, as Line
            rel = p - self._start[0]
            n = self._normal[0]
            return rel[:, 1] * n[1] if n[0] == 0.0 else rel[:, 0] * n[0] + rel[:, 1] * n[1]
        _, dist, _ = self._feet(p)
        d = dist.min(axis=1)
        return np.where(p[:, 1] >= self.z(p[:, 0]), d, -d)

    def landing_time(self, xy: np.ndarray, velocity: np.ndarray) -> np.ndarray:
        """Time for each point moving at ``velocity`` to reach the bed (inf if never): the
        first crossing of a segment's line at a point of that segment."""
        p = np.asarray(xy, dtype=float).reshape(-1, 2)
        w = np.asarray(velocity, dtype=float).reshape(-1, 2)
        if self.segments == 1:
            rel = p - self._start[0]
            n = self._normal[0]
            h = rel[:, 1] * n[1] if n[0] == 0.0 else rel[:, 0] * n[0] + rel[:, 1] * n[1]
            v = w[:, 1] * n[1] if n[0] == 0.0 else w[:, 0] * n[0] + w[:, 1] * n[1]
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.where(v < 0, h / -v, np.inf)
        rel = p[:, None, :] - self._start[None]
        n, t = self._normal[None], self._tangent[None]
        h = rel[..., 0] * n[..., 0] + rel[..., 1] * n[..., 1]
        v = w[:, None, 0] * n[..., 0] + w[:, None, 1] * n[..., 1]
        with np.errstate(divide="ignore", invalid="ignore"):   # (below a segment's line:
            time = np.where((v < 0) & (h >= -REACHED), np.maximum(h, 0.0) / -v, np.inf)
        hit = rel + np.where(np.isfinite(time), time, 0.0)[..., None] * w[:, None, :]
        s = hit[..., 0] * t[..., 0] + hit[..., 1] * t[..., 1]
        slack = 1e-9 * self._length
        lo, hi = -slack, self._length + slack
        lo[0], hi[-1] = -np.inf, np.inf
        time = np.where((s >= lo) & (s <= hi), time, np.inf)
        return time.min(axis=1)

    def on(self, xy: np.ndarray, tol: float) -> np.ndarray:
        """Whether each point lies within ``tol`` above (or anywhere below) the bed."""
        return self.height(xy) <= tol

    # --- the bed followed ---------------------------------------------------------------
    def arc_length(self, x: np.ndarray | float) -> np.ndarray:
        """Distance along the bed from its first point to the point above x."""
        xs = np.atleast_1d(np.asarray(x, dtype=float))
        k = self.segment_of(xs)
        before = np.concatenate([[0.0], np.cumsum(self._length)])[k]
        return before + (xs - self._start[k, 0]) / self._tangent[k, 0]

    def at_arc_length(self, s: np.ndarray | float) -> tuple[np.ndarray, np.ndarray]:
        """The bed point at distance s along it, and the index of its segment."""
        ss = np.atleast_1d(np.asarray(s, dtype=float))
        ends = np.concatenate([[0.0], np.cumsum(self._length)])
        k = np.clip(np.searchsorted(ends, ss, side="right") - 1, 0, self.segments - 1)
        local = ss - ends[k]
        return self._start[k] + local[:, None] * self._tangent[k], k

    def between(self, s0: float, s1: float) -> np.ndarray:
        """The bed from arc length s0 to s1 as a polyline (its corners included)."""
        ends = np.concatenate([[0.0], np.cumsum(self._length)])
        inner = self.points[(ends > s0) & (ends < s1)]
        first, _ = self.at_arc_length(s0)
        last, _ = self.at_arc_length(s1)
        return np.vstack([first, inner, last])

    def offset(self, distance: float, s0: float, s1: float) -> np.ndarray:
        """The curve ``distance`` above the bed from arc length s0 to s1 (normal to each
        segment, joined with mitres at the corners), as a polyline."""
        base = self.between(s0, s1)
        d = np.diff(base, axis=0)
        t = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        n = np.column_stack([-t[:, 1], t[:, 0]])
        out = [base[0] + distance * n[0]]
        for i in range(1, len(base) - 1):
            bisector = n[i - 1] + n[i]
            out.append(base[i] + distance * bisector / np.dot(bisector, n[i]))
        out.append(base[-1] + distance * n[-1])
        return np.array(out)


def _dot(a: np.ndarray, b: tuple[float, float] | np.ndarray) -> np.ndarray:
    a = np.asarray(a, dtype=float).reshape(-1, 2)
    if b[1] == 0.0:
        return a[:, 0] * b[0]
    if b[0] == 0.0:
        return a[:, 1] * b[1]
    return a[:, 0] * b[0] + a[:, 1] * b[1]
