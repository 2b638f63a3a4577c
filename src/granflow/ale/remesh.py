"""Remeshing of the moving domain when the ALE mesh degrades (reliability; issue 9).

The boundary polygon is kept exactly (every boundary vertex stays a geometry point, with
its label), long boundary edges are split by Netgen at the target size, and the interior
is triangulated anew. Fields are then interpolated onto the new mesh, which is the only
place where granflow interpolates the velocity.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.ale.free_surface import BoundaryChain
from granflow.fem.sampling import triangles
from granflow.geometry.mesh import BED, SURFACE, WALL, polygon_mesh

STRAIGHT_DEG = 2.0  # a free-surface vertex turning the surface by less is dropped on remeshing


def shape_quality(mesh: ngs.Mesh) -> np.ndarray:
    """4 sqrt(3) area / (sum of squared edge lengths): 1 equilateral, 0 flat or inverted."""
    xy = mesh.ngmesh.Coordinates()
    p = xy[triangles(mesh)]
    e = np.roll(p, -1, axis=1) - p
    area = 0.5 * (e[:, 0, 0] * e[:, 1, 1] - e[:, 0, 1] * e[:, 1, 0])
    return 4.0 * np.sqrt(3.0) * area / np.sum(e**2, axis=(1, 2))


def boundary_loop(chain: BoundaryChain) -> tuple[np.ndarray, list[str]]:
    """Vertex indices around the boundary (counter-clockwise) and the label of each edge."""
    names = {index: name for name, index in chain.index.items()}
    segments, labels = chain.segments, chain.labels()
    after = {int(a): (int(b), names[int(lab)]) for (a, b), lab in
             zip(segments, labels, strict=True)}
    start = int(segments[0, 0])
    loop, edge_labels, v = [start], [], start
    while True:
        v, label = after[v]
        edge_labels.append(label)
        if v == start:
            break
        loop.append(v)
    if len(loop) != len(segments):
        raise RuntimeError("the boundary is not a single closed loop; cannot remesh")
    return np.array(loop), edge_labels


def remesh(mesh: ngs.Mesh, size: float) -> ngs.Mesh:
    """A fresh Netgen mesh of the current domain with the same labelled boundary.

    Vertices inside a straight run of bed or wall edges are dropped (the run is one line,
    which Netgen splits at ``size``), and so are free-surface vertices where the surface
    turns by less than ``STRAIGHT_DEG``: three such vertices would otherwise make a flat
    triangle with two boundary edges, which inverts as the surface straightens. The area
    this removes (a sliver) is restored by the area correction of the next move.
    """
    loop, labels = boundary_loop(BoundaryChain(mesh))
    xy = mesh.ngmesh.Coordinates()
    pts = xy[loop]
    before, after = pts - np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0) - pts
    turn = np.degrees(np.abs(np.arctan2(
        before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0],
        np.sum(before * after, axis=1))))
    keep, dropped_previous = [], False
    for i in range(len(loop)):
        straight_run = labels[i - 1] == labels[i] and labels[i] in (BED, WALL)
        flat = labels[i - 1] == labels[i] == SURFACE and turn[i] < STRAIGHT_DEG
        if straight_run or (flat and not dropped_previous):  # never two surface nodes in a row
            dropped_previous = flat
            continue
        dropped_previous = False
        keep.append(i)
    points = [tuple(xy[loop[i]]) for i in keep]
    edge_labels = [labels[i] for i in keep]  # the edge leaving a kept vertex keeps its label
    return polygon_mesh(points, edge_labels, size)
