"""The free surface of a 3D column cut by a plane across the channel (Y = const): its trace
as a polyline (X, Z) from the back wall to the front, read by the outputs (the surface along
the centre line and at the side wall) and by the remesh (the sections a new body is lofted
through, ``geometry/mesh3d.py: lofted_mesh``)."""

from __future__ import annotations

from collections import defaultdict

import ngsolve as ngs
import numpy as np

from granflow.geometry.labels import SURFACE
from granflow.geometry.mesh3d import ON_PLANE, boundary_faces

Key = tuple[int, int]   # a point of the trace: a vertex (i, i) or the crossing of edge (i, j)


def plane_section(mesh: ngs.Mesh, y: float, tol: float = ON_PLANE) -> np.ndarray:
    """(n, 2) points (X, Z) where the free surface meets the plane Y = y, chained from the
    end nearest the back wall to the front; empty when the plane misses the surface."""
    faces, labels = boundary_faces(mesh)
    xyz = mesh.ngmesh.Coordinates()
    side = xyz[:, 1] - y
    on = np.abs(side) < tol
    points: dict[Key, np.ndarray] = {}
    links: dict[Key, set[Key]] = defaultdict(set)

    def point(i: int, j: int) -> Key:
        key = (min(i, j), max(i, j))
        if key not in points:
            if i == j:
                points[key] = xyz[i, [0, 2]]
            else:
                s = side[i] / (side[i] - side[j])
                points[key] = (xyz[i] + s * (xyz[j] - xyz[i]))[[0, 2]]
        return key

    for tri in faces[labels == SURFACE]:
        lying = [int(v) for v in tri if on[v]]
        crossed = [(int(a), int(b)) for a, b in ((tri[0], tri[1]), (tri[1], tri[2]),
                                                 (tri[2], tri[0]))
                   if not on[a] and not on[b] and side[a] * side[b] < 0]
        ends = [point(v, v) for v in lying] + [point(a, b) for a, b in crossed]
        if len(ends) == 2 and ends[0] != ends[1]:
            links[ends[0]].add(ends[1])
            links[ends[1]].add(ends[0])
    return _chain(points, links)


def _chain(points: dict[Key, np.ndarray], links: dict[Key, set[Key]]) -> np.ndarray:
    """The longest path through the links (a surface cut by a plane: one open chain),
    from its end of least X."""
    seen: set[Key] = set()
    best: list[Key] = []
    for start in sorted(links, key=lambda k: (len(links[k]) != 1, points[k][0])):
        if start in seen:
            continue
        path, previous, current = [start], None, start
        seen.add(start)
        while True:
            ahead = [k for k in links[current] if k != previous and k not in seen]
            if not ahead:
                break
            previous, current = current, ahead[0]
            seen.add(current)
            path.append(current)
        if len(path) > len(best):
            best = path
    if not best:
        return np.empty((0, 2))
    out = np.array([points[k] for k in best])
    return out if out[0, 0] <= out[-1, 0] else out[::-1]


def front_of(section: np.ndarray) -> float:
    """The front's X on a section (the largest X of its trace; 0 for an empty one)."""
    return float(section[:, 0].max()) if len(section) else 0.0


def section_polygon(section: np.ndarray, count: int, floor: float) -> np.ndarray:
    """The closed section through a trace (from the back wall to the front): (0, 0), the
    front's foot on the bed, then ``count`` - 1 points equally spaced along the surface back
    to the wall. The part of the trace that lies on the bed (within ``floor`` above it, at
    the front) is bed: the foot is where the surface comes down to it."""
    trace = section.copy()
    trace[0, 0] = 0.0                          # on the back wall
    high = np.flatnonzero(trace[:, 1] > floor)
    last = min(int(high[-1]) + 1, len(trace) - 1) if high.size else len(trace) - 1
    trace = trace[: last + 1]
    trace[-1, 1] = 0.0                         # the foot, on the bed
    lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(trace, axis=0),
                                                              axis=1))])
    s = np.linspace(0.0, lengths[-1], count)
    surface = np.column_stack([np.interp(s, lengths, trace[:, 0]),
                               np.interp(s, lengths, trace[:, 1])])
    return np.vstack([[0.0, 0.0], surface[::-1]])
