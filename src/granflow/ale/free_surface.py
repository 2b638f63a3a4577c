"""The boundary of a column mesh: its labelled segments, the free-surface chains, and the
geometric checks and area of the boundary polygon.

Works on the live Netgen mesh: vertex positions are read from ``Coordinates()``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from scipy.spatial import cKDTree

from granflow.geometry.mesh import BED, END, LABELS, SURFACE, WALL
from granflow.geometry.section import (  # noqa: F401  (also read from here)
    PLANE_SECTION,
    REVOLVED_SECTION,
    area_gradient,
    polygon_area,
    revolved_volume,
    revolved_volume_gradient,
)

LONG = 4.0   # segments_intersect: segments longer than this x the median are paired with all


class BoundaryChain:
    """Boundary segments of a mesh with their labels (bed, wall, surface)."""

    def __init__(self, mesh: ngs.Mesh) -> None:
        self.mesh = mesh
        names = [mesh.ngmesh.GetBCName(i) for i in range(len(mesh.GetBoundaries()))]
        self.index = {name: names.index(name) + 1 for name in LABELS if name in names}

    @property
    def segments(self) -> np.ndarray:
        """(ns, 2) zero-based vertex indices of the boundary segments."""
        return self.mesh.ngmesh.Elements1D().NumPy()["nodes"][:, :2].astype(np.int64) - 1

    def labels(self) -> np.ndarray:
        return self.mesh.ngmesh.Elements1D().NumPy()["index"].copy()

    def vertices(self, label: str) -> np.ndarray:
        """Vertices on at least one segment of ``label``."""
        if label not in self.index:
            return np.empty(0, dtype=np.int64)
        seg = self.segments[self.labels() == self.index[label]]
        return np.unique(seg)

    def free_vertices(self) -> np.ndarray:
        """Surface vertices that touch neither the bed nor the wall."""
        surface = self.vertices(SURFACE)
        fixed = np.union1d(np.union1d(self.vertices(BED), self.vertices(WALL)),
                           self.vertices(END))
        return np.setdiff1d(surface, fixed)

    def surface_chains(self) -> list[np.ndarray]:
        """Vertex indices of each surface chain, from its wall side to its front end.

        The boundary runs counter-clockwise, so each chain runs from its front end towards
        the wall; deposition can split the surface into several chains (a bed edge between
        them). Chains are listed from the wall outwards.
        """
        xy = self.mesh.ngmesh.Coordinates()
        seg = self.segments[self.labels() == self.index[SURFACE]]
        nxt = {int(a): int(b) for a, b in seg}
        starts = sorted(set(nxt) - {int(b) for b in seg[:, 1]}, key=lambda v: -xy[v, 0])
        if not starts:
            starts = [int(seg[0, 0])]
        chains: list[np.ndarray] = []
        for start in starts:
            v, chain = start, [start]
            while v in nxt and len(chain) <= 2 * len(seg):
                v = nxt[v]
                chain.append(v)
            chains.append(np.array(chain[::-1], dtype=np.int64))
        return chains[::-1]

    def surface_polyline(self) -> np.ndarray:
        """Surface vertex coordinates from the wall top to the front (all chains joined)."""
        xy = self.mesh.ngmesh.Coordinates()
        return xy[np.concatenate(self.surface_chains())]



def segments_intersect(xy: np.ndarray, segments: np.ndarray) -> bool:
    """True if two non-adjacent boundary segments cross (the surface folded through)."""
    return len(crossing_segments(xy, segments)) > 0


def crossing_segments(xy: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """(k, 2) indices of the pairs of non-adjacent boundary segments that cross.

    Two segments can only cross if their midpoints lie within the longer one's length of
    each other. The candidate pairs among the segments up to LONG x the median length come
    from a k-d tree (scipy); the few longer ones are paired with every segment. A long
    boundary (a 3 m erodible layer: 1,500 segments) then costs O(n log n) instead of the
    n^2 / 2 pairs of the exact test, with the same answer.
    """
    p, q = xy[segments[:, 0]], xy[segments[:, 1]]
    d = q - p
    length = np.hypot(d[:, 0], d[:, 1])
    n = len(segments)
    none = np.empty((0, 2), dtype=np.int64)
    if n < 2:
        return none
    long = length > LONG * np.median(length)
    short = np.flatnonzero(~long)
    reach = float(np.max(length[short], initial=0.0)) * (1 + 1e-9)
    near = cKDTree(0.5 * (p + q)[short]).query_pairs(reach, output_type="ndarray")
    pairs = [short[near]] if len(near) else []
    for k in np.flatnonzero(long):
        others = np.delete(np.arange(n), k)
        pairs.append(np.column_stack([np.full(len(others), k), others]))
    if not pairs:
        return none
    i, j = np.concatenate(pairs).T
    return crossing(xy, segments, i, j)


def pairs_cross(xy: np.ndarray, segments: np.ndarray, i: np.ndarray, j: np.ndarray) -> bool:
    """True if, among the segment pairs (i[k], j[k]), two that share no vertex cross
    properly (each one's end points strictly on both sides of the other's line)."""
    return len(crossing(xy, segments, i, j)) > 0


def crossing(xy: np.ndarray, segments: np.ndarray, i: np.ndarray, j: np.ndarray
             ) -> np.ndarray:
    """The segment pairs (i[k], j[k]) that share no vertex and cross properly, (k, 2)."""
    p, q = xy[segments[:, 0]], xy[segments[:, 1]]
    d = q - p
    share = np.any(segments[i][:, :, None] == segments[j][:, None, :], axis=(1, 2))
    i, j = i[~share], j[~share]

    def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]

    r = cross(d[i], p[j] - p[i]), cross(d[i], q[j] - p[i])
    s = cross(d[j], p[i] - p[j]), cross(d[j], q[i] - p[j])
    hit = (r[0] * r[1] < 0) & (s[0] * s[1] < 0)
    return np.column_stack([i[hit], j[hit]])


def pocket(segments: np.ndarray, labels: np.ndarray, surface: int,
           pairs: np.ndarray) -> np.ndarray:
    """The free-surface vertices a fold encloses: for each crossing pair of boundary
    segments, the vertices between them along the boundary, the shorter way round, when
    every edge on that way is free surface (a pocket of the surface closing on itself,
    never one cut off by the bed or a wall). Dropped by the remesh, they leave the surface
    running straight across the pocket, as ``ale/remesh.close_folds`` does where a fold
    has touched."""
    after = dict(segments.tolist())
    label_of = {int(a): int(lab) for (a, _), lab in zip(segments, labels, strict=True)}
    loop = [int(segments[0, 0])]
    while len(loop) < len(segments) and after[loop[-1]] != loop[0]:
        loop.append(after[loop[-1]])
    at = {v: k for k, v in enumerate(loop)}
    n, out = len(loop), set()
    for a, b in pairs:
        ka, kb = at[int(segments[a, 0])], at[int(segments[b, 0])]
        first, count = (ka, (kb - ka) % n) if (kb - ka) % n <= (ka - kb) % n else (
            kb, (ka - kb) % n)
        inside = [loop[(first + k) % n] for k in range(1, count + 1)]
        edges = [loop[(first + k) % n] for k in range(count + 1)]
        if all(label_of[v] == surface for v in edges):
            out.update(inside)
    return np.array(sorted(out), dtype=np.int64)


@dataclass(frozen=True)
class PolygonMeasure:
    """What the free-surface fixes conserve: the section's area in plane strain, the
    revolved volume in axisymmetry (incompressible flow conserves the one that is the
    body's volume), with its gradient."""

    size: Callable[[np.ndarray, np.ndarray], float]
    gradient: Callable[[np.ndarray, np.ndarray], np.ndarray]


AREA = PolygonMeasure(PLANE_SECTION.polygon, PLANE_SECTION.polygon_gradient)
REVOLVED = PolygonMeasure(REVOLVED_SECTION.polygon, REVOLVED_SECTION.polygon_gradient)


def polygon_measure(axisymmetric: bool) -> PolygonMeasure:
    return REVOLVED if axisymmetric else AREA


def conserve_area(xy: np.ndarray, segments: np.ndarray, movable: np.ndarray,
                  target: float, iterations: int = 3,
                  measure: PolygonMeasure = AREA) -> float:
    """Shift ``movable`` vertices along the gradient of ``measure`` (the area, or the revolved
    volume in axisymmetry) so that the polygon's measure is ``target``.

    The smallest displacement (in the least-squares sense) that restores the area: the
    discrete velocity carries no net flux through the boundary (Taylor–Hood, integral of
    div u_h = 0), so any area change comes from moving straight edges and is removed.
    Returns the relative area change applied, signed: (after - before) / target.
    """
    before = measure.size(xy, segments)
    for _ in range(iterations):
        g = measure.gradient(xy, segments)[movable]
        denom = float(np.sum(g * g))
        if denom == 0:
            break
        delta = (target - measure.size(xy, segments)) / denom
        xy[movable] += delta * g
    return (measure.size(xy, segments) - before) / abs(target)


def conserve_above(xy: np.ndarray, segments: np.ndarray, movable: np.ndarray, target: float,
                   height: Callable[[np.ndarray], np.ndarray],
                   measure: PolygonMeasure = AREA) -> float:
    """``conserve_area``, holding where they were the vertices it would push through the bed
    (``height`` below 0 after the fix, not before); the others carry the whole fix.

    The fix's shift does not shrink with the step: after a remesh that lost a sliver's
    area (a flat corner collapsed), it moves every free vertex by up to 5e-8 m at once,
    and a rolling nose's underside lying 1e-9 m above a no-slip bed would be pushed under
    it at every step size, each move refused. Where nothing is pushed through, the result
    is ``conserve_area``'s, unchanged. Returns the relative change applied."""
    start = xy[movable].copy()
    below = height(start) < 0
    while True:
        applied = conserve_area(xy, segments, movable, target, measure=measure)
        through = (height(xy[movable]) < 0) & ~below
        if not through.any() or through.all():
            return applied
        xy[movable] = start
        movable, start, below = movable[~through], start[~through], below[~through]


def bed_overlaps(xy: np.ndarray, segments: np.ndarray, height: Callable[[np.ndarray], np.ndarray],
                 along: Callable[[np.ndarray], np.ndarray], tol: float) -> np.ndarray:
    """(k, 2) pairs of boundary segments lying on the bed (both ends within ``tol`` of it by
    ``height``) that share no vertex and overlap along it (by more than ``tol`` in ``along``,
    the distance along the bed): a surface vertex landed on bed the material already
    covers. The crossing test (``crossing``) cannot see it: the two segments are collinear."""
    down = height(xy) <= tol
    flat = np.flatnonzero(down[segments[:, 0]] & down[segments[:, 1]])
    if len(flat) < 2:
        return np.empty((0, 2), dtype=np.int64)
    s = along(xy[:, 0])[segments[flat]]
    lo, hi = s.min(axis=1), s.max(axis=1)
    order = np.argsort(lo)
    lo, hi, flat = lo[order], hi[order], flat[order]
    reach = np.maximum.accumulate(hi)          # the furthest any earlier segment reaches
    out = []
    for k in np.flatnonzero(reach[:-1] > lo[1:] + tol) + 1:
        for j in np.flatnonzero(hi[:k] > lo[k] + tol):
            a, b = flat[j], flat[k]
            if not np.intersect1d(segments[a], segments[b]).size:
                out.append((a, b))
    return np.array(out, dtype=np.int64).reshape(-1, 2)


def overlap_pocket(segments: np.ndarray, labels: np.ndarray, surface: int,
                   pairs: np.ndarray) -> np.ndarray:
    """The free-surface vertices between two overlapping bed segments (``bed_overlaps``):
    for each pair, the inner vertices of the way along the boundary from the end of one to
    the start of the other, the shorter way round, when every edge on it is free surface
    (a pocket of the surface landed on bed the material covers). Dropped by the remesh,
    they leave the two bed segments meeting in a spike that ``ale/remesh.drop_spikes``
    removes: the pocket closes onto the bed."""
    after = dict(segments.tolist())
    label_of = {int(a): int(lab) for (a, _), lab in zip(segments, labels, strict=True)}
    out: set[int] = set()
    for a, b in pairs:
        ways = []
        for first, last in ((int(segments[a, 1]), int(segments[b, 0])),
                            (int(segments[b, 1]), int(segments[a, 0]))):
            way = [first]
            while way[-1] != last and len(way) <= len(segments):
                way.append(int(after[way[-1]]))
            ways.append(way)
        way = min(ways, key=len)
        if all(label_of[v] == surface for v in way[:-1]):
            out.update(way[1:-1])
    return np.array(sorted(out), dtype=np.int64)
