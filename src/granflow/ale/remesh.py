"""Remeshing of the moving domain when the ALE mesh degrades (reliability).

The boundary polygon is kept exactly (every boundary vertex stays a geometry point, with
its label), long boundary edges are split by Netgen at the target size, and the interior
is triangulated anew. Fields are then interpolated onto the new mesh, which is the only
place where granflow interpolates the velocity.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from granflow.ale.free_surface import (
    AREA,
    BoundaryChain,
    PolygonMeasure,
    conserve_area,
    segments_intersect,
)
from granflow.fem.sampling import triangles
from granflow.geometry.mesh import (
    BED,
    END,
    GATE,
    SURFACE,
    WALL,
    polygon_mesh,
    triangle_quality,
)
from granflow.geometry.profile import CORNER_DEG, BedProfile
from granflow.geometry.stretch import ISOTROPIC, LayerStretch

STRAIGHT_DEG = 2.0  # a free-surface vertex turning the surface by less is dropped on remeshing
MIN_SURFACE_EDGE = 0.1  # surface vertices closer than this x mesh.size to a kept one are dropped
FOLD_GAP = 0.25  # a surface vertex this close (x its shortest edge) to another surface edge
SNAP_CORNER = 0.2  # a bed vertex this close (x its edge) to a bed corner it passed is put on it
SPIKE_RAD = 1e-3  # a boundary vertex whose two edges meet at a smaller angle is dropped
TOUCH = 1e-9  # a surface vertex this close (x its shortest edge) to another surface edge


def shape_quality(mesh: ngs.Mesh, stretch: LayerStretch = ISOTROPIC) -> np.ndarray:
    """4 sqrt(3) area / (sum of squared edge lengths): 1 equilateral, 0 flat or inverted;
    measured in the coordinates the mesh was made in (``stretch``: a stretched layer's
    cells are as good as isotropic ones there)."""
    return triangle_quality(stretch.forward(mesh.ngmesh.Coordinates()), triangles(mesh))


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


EdgeSize = Callable[[np.ndarray, np.ndarray], float]


@dataclass(frozen=True)
class Remeshed:
    """A new mesh, and the relative area its simplified boundary lost before the free
    surface was shifted to restore it (``area_restored``; the remesh itself conserves
    the area to round-off)."""

    mesh: ngs.Mesh
    area_restored: float
    area_added: float = 0.0   # what lengthening an erodible layer added (m^2, or m^3 in r-z)


def remesh(mesh: ngs.Mesh, size: float, edge_size: EdgeSize | None = None,
           measure: PolygonMeasure = AREA, layer_end: float | None = None,
           layer_top: float = 0.0, stretch: LayerStretch = ISOTROPIC,
           bed: BedProfile | None = None, maxh: float | None = None,
           restrict: np.ndarray | None = None, cut: np.ndarray | None = None) -> Remeshed:
    """A fresh Netgen mesh of the current domain with the same labelled boundary.

    Vertices inside a straight run of bed or wall edges are dropped (the run is one line,
    which Netgen splits at ``size``); the corners of the bed profile ``bed`` under a bed
    edge are inserted and kept (``with_bed_corners``); free-surface vertices where the surface
    turns by less than ``STRAIGHT_DEG``: three such vertices would otherwise make a flat
    triangle with two boundary edges, which inverts as the surface straightens. Surface
    vertices bunched closer than ``MIN_SURFACE_EDGE * size`` are merged: (3.7) lets nodes
    slide along the surface, and where they converge they can overtake one another and
    fold the surface into a hairpin of zero thickness. The area these simplifications
    change (up to 0.3 % of the column on a coarse mesh) is restored at once by shifting the
    inner free-surface vertices along the area gradient (``conserve_area``, as after every
    move), so a remesh changes the area only by round-off. ``edge_size(p, q)``, if given,
    is the target length on the boundary edge from p to q (a thin erodible layer).
    ``measure``: what is restored, the area, or the revolved volume in axisymmetry.
    ``layer_end``, if given, moves the far end of an erodible layer there, the new stretch
    of layer ``layer_top`` thick (``lengthen_layer``); its size is ``area_added``.
    ``stretch``: the layer's cells stretched along it, as the first mesh made them
    (``edge_size`` then gives lengths in the stretched coordinates). ``maxh`` (default
    ``size``) is the largest edge and ``restrict`` (k, 3) the points (x, z, h) where the
    mesh must be finer (a size field from the flow, ``ale/size_field.py``). ``cut``: inner
    free-surface vertices dropped at once, the pocket a move found folding over
    (``free_surface.pocket``): the surface then runs straight across it, as where a fold
    has touched (``close_folds``), and the area fix restores the area it filled.
    """
    loop, labels = boundary_loop(BoundaryChain(mesh))
    xy = mesh.ngmesh.Coordinates()
    area = measure.size(xy[loop], _ring(len(loop)))
    if cut is not None and len(cut):
        kept = ~np.isin(loop, cut)
        loop, labels = loop[kept], [lab for lab, k in zip(labels, kept, strict=True) if k]
    loop_xy, labels = with_bed_corners(xy[loop], labels, bed)
    keep = kept_boundary_vertices(loop_xy, labels, MIN_SURFACE_EDGE * size)
    points = [tuple(loop_xy[i]) for i in keep]
    edge_labels = [labels[i] for i in keep]  # the edge leaving a kept vertex keeps its label
    points, edge_labels = drop_spikes(*close_folds(*drop_touching(points, edge_labels)))
    n = len(points)
    ring = _ring(n)
    pts = np.array(points, dtype=float)
    inner = np.array([i for i in range(n) if edge_labels[i - 1] == edge_labels[i] == SURFACE])
    restored = conserve_area(pts, ring, inner, area, measure=measure) if inner.size else 0.0
    added = 0.0
    if layer_end is not None:
        before = measure.size(pts, ring)
        points, edge_labels = lengthen_layer([tuple(p) for p in pts], edge_labels, layer_end,
                                             layer_top)
        pts, ring = np.array(points, dtype=float), _ring(len(points))
        added = measure.size(pts, ring) - before
    if segments_intersect(pts, ring):
        raise RuntimeError("the free surface folded through itself and merging close surface "
                           "nodes does not untangle it; cannot remesh")
    points = [tuple(p) for p in pts]
    new = polygon_mesh(points, edge_labels, size if maxh is None else maxh,
                       boundary_edge_sizes(points, edge_size), stretch=stretch,
                       restrict=restrict)
    return Remeshed(new, restored, added)


def lengthen_layer(points: list[tuple[float, float]], labels: list[str], end_x: float,
                   top: float) -> tuple[list[tuple[float, float]], list[str]]:
    """The polygon with its erodible layer's far end (the one ``end`` edge, from its foot on
    the bed up to the layer's top) moved on to X = ``end_x``: the bed runs on to there, the
    end rises to ``top`` (the undisturbed layer's thickness) and a free surface comes back
    to the old top corner. The added stretch is layer at rest, which the old end wall held
    in place. Unchanged if ``end_x`` is not beyond the old end."""
    ends = [i for i, label in enumerate(labels) if label == END]
    if len(ends) != 1:
        raise RuntimeError(f"the layer's far end is {len(ends)} edges, not one; cannot "
                           "lengthen the layer")
    i = ends[0]
    if end_x <= points[i][0]:
        return points, labels
    return ([*points[:i], (end_x, 0.0), (end_x, top), *points[i + 1:]],
            [*labels[:i], END, SURFACE, *labels[i + 1:]])


def with_bed_corners(pts: np.ndarray, labels: list[str], bed: BedProfile | None
                     ) -> tuple[np.ndarray, list[str]]:
    """The boundary loop with the bed profile's corners inserted into the bed edges that
    pass over them (a node that slid through a corner left a chord across it)."""
    if bed is None or not len(bed.corners()):
        return pts, labels
    corners = bed.corners()
    pts = pts.copy()
    out, out_labels = [], []
    n = len(pts)
    for i in range(n):
        p, q = pts[i], pts[(i + 1) % n]
        out.append(p)
        out_labels.append(labels[i])
        if labels[i] == BED:
            lo, hi = min(p[0], q[0]), max(p[0], q[0])
            inner = corners[(corners[:, 0] > lo) & (corners[:, 0] < hi)]
            inner = inner[np.argsort(inner[:, 0] * np.sign(q[0] - p[0]))]
            near = SNAP_CORNER * np.hypot(*(q - p))
            p_held, q_held = labels[i - 1] == BED, labels[(i + 1) % n] == BED
            for c in inner:     # a bed node that has only just slid past: back onto it
                if np.hypot(*(c - p)) < near:
                    if p_held:
                        out[-1] = p = c
                elif np.hypot(*(c - q)) < near:
                    if q_held:
                        pts[(i + 1) % n] = q = c
                else:           # (a contact point just past it: later, once further)
                    out.append(c)
                    out_labels.append(BED)
    if not np.array_equal(out[0], pts[0]):   # the first vertex moved as the last edge's end
        out[0] = pts[0]
    return np.array(out), out_labels


def straddled_corners(pts: np.ndarray, held: np.ndarray, bed: BedProfile, tol: float) -> int:
    """How many bed edges (``pts`` (k, 2, 2): their ends; ``held`` (k, 2): whether each end
    is a bed node, not a contact point) pass over a corner of the bed profile more than
    ``tol`` away from it, where a remesh would put a vertex on the corner (``with_bed_corners``:
    not while a contact point is within SNAP_CORNER of an edge from it)."""
    corners = bed.corners()
    if not len(corners) or not len(pts):
        return 0
    lo, hi = pts[:, :, 0].min(axis=1), pts[:, :, 0].max(axis=1)
    count = 0
    for c in corners:
        over = np.flatnonzero((lo < c[0]) & (hi > c[0]))
        for k in over:
            p, q = pts[k]
            s = (c[0] - p[0]) / (q[0] - p[0])
            if abs(p[1] + s * (q[1] - p[1]) - c[1]) <= tol:
                continue
            near = SNAP_CORNER * np.hypot(*(q - p))
            close = np.hypot(*(pts[k] - c).T) < near
            if not np.any(close & ~held[k]):
                count += 1
    return count


def _ring(n: int) -> np.ndarray:
    return np.array([[i, (i + 1) % n] for i in range(n)])


def boundary_edge_sizes(points: Sequence[tuple[float, float]],
                        edge_size: EdgeSize | None) -> list[float] | None:
    """Target length of each edge of the closed polygon ``points`` (None: the global size)."""
    if edge_size is None:
        return None
    pts = np.asarray(points, dtype=float)
    return [edge_size(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]


def close_folds(points: list[tuple[float, float]], labels: list[str],
                gap: float = FOLD_GAP) -> tuple[list[tuple[float, float]], list[str]]:
    """Cut the pocket where the free surface has folded onto itself.

    Where an inner surface vertex i has come closer than ``gap`` x its shortest adjacent
    edge to a non-adjacent surface edge (over an erodible layer, the overturning front
    touching down on the layer), the surface vertices between them (the fold's pocket,
    the shorter way round) are dropped, so the surface runs from i straight to the far
    end of that edge: the void closes and becomes material (the area correction of the
    next move restores the area). This is what the surface tension of section 3.4 does
    gradually; a remesh needs it done at once when the fold has already touched.
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    on_surface = np.array(labels) == SURFACE
    start, d = pts, np.roll(pts, -1, axis=0) - pts          # edge j runs from j to j + 1
    d2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    inner = [i for i in range(n) if labels[i - 1] == labels[i] == SURFACE]
    for i in inner:
        edge = min(np.linalg.norm(pts[i] - pts[i - 1]), np.linalg.norm(pts[(i + 1) % n] - pts[i]))
        s = np.clip(np.einsum("ij,ij->i", pts[i] - start, d) / d2, 0, 1)
        close = on_surface & (np.linalg.norm(pts[i] - (start + s[:, None] * d), axis=1)
                              < gap * edge)
        close[[i, (i - 1) % n]] = False                # the edges at i itself
        for j in np.flatnonzero(close):
            forward = (j - i) % n        # vertices i+1..j lie between i and the edge
            backward = (i - j - 1) % n   # vertices j+1..i-1 lie between the edge and i
            if forward <= backward:
                drop = {(i + k) % n for k in range(1, forward + 1)}
            else:
                drop = {(j + k) % n for k in range(1, backward + 1)}
            if any(labels[k - 1] != SURFACE or labels[k] != SURFACE for k in drop):
                continue                  # never cut through a contact point or a wall
            keep = [k for k in range(n) if k not in drop]
            return close_folds([points[k] for k in keep], [labels[k] for k in keep], gap)
    return points, labels


def drop_touching(points: list[tuple[float, float]], labels: list[str],
                  touch: float = TOUCH) -> tuple[list[tuple[float, float]], list[str]]:
    """The boundary loop without the inner surface vertices that touch another surface edge.

    A front folded twice (an overturned nose whose top runs back, then forward again under
    itself) can bring a surface vertex onto the nose's underside (to 5e-15 m) without any
    edge crossing: the domain is two lobes meeting at that point. Netgen cannot mesh a
    boundary touching itself, and ``close_folds``, cutting the thin lobes' pockets one at a
    time, can leave edges crossing there. The vertex's two edges lie on the touched edge's
    material side, so between them is an air sector of the fold (or a tip of material):
    dropping the vertex fills that sector's apex (cuts the tip), the triangle on its two
    edges, and joins the lobes; the area fix restores the area it changed. Edges at the
    vertex's neighbours are not touches but spikes (``drop_spikes``).
    """
    pts = np.asarray(points, dtype=float)
    n = len(pts)
    on_surface = np.array(labels) == SURFACE
    start, d = pts, np.roll(pts, -1, axis=0) - pts          # edge j runs from j to j + 1
    d2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    for i in range(n):
        if not labels[i - 1] == labels[i] == SURFACE or n <= 4:
            continue
        edge = min(np.linalg.norm(pts[i] - pts[i - 1]), np.linalg.norm(pts[(i + 1) % n] - pts[i]))
        s = np.clip(np.einsum("ij,ij->i", pts[i] - start, d) / d2, 0, 1)
        touching = on_surface & (np.linalg.norm(pts[i] - (start + s[:, None] * d), axis=1)
                                 < touch * edge)
        touching[[(i - 2) % n, (i - 1) % n, i, (i + 1) % n]] = False
        if touching.any():
            keep = [k for k in range(n) if k != i]
            return drop_touching([points[k] for k in keep], [labels[k] for k in keep], touch)
    return points, labels


def drop_spikes(points: list[tuple[float, float]], labels: list[str],
                min_angle: float = SPIKE_RAD) -> tuple[list[tuple[float, float]], list[str]]:
    """The boundary loop without the tips of zero-thickness spikes and cracks.

    Where the two edges at a vertex meet at less than ``min_angle`` (a free surface lying
    back along the bed from the front's contact point, 1e-12 m above it, after a run
    spread a film: a tongue a thousand times longer than thick), Netgen fails (angles near
    1e-4) or never returns (1e-6 and below). The tip is dropped and its two edges become
    one, which keeps a bed, wall or end label over a surface one: the nearly landed
    vertex becomes the contact point. The area lost is the spike's, of the order of the
    angle times its length squared.
    """
    pts = np.asarray(points, dtype=float)
    a, b = np.roll(pts, 1, axis=0) - pts, np.roll(pts, -1, axis=0) - pts
    angle = np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
    tips = np.flatnonzero(angle < min_angle)
    if not tips.size or len(points) <= 3:
        return points, labels
    i = int(tips[0])
    merged = labels[i - 1] if labels[i - 1] != SURFACE else labels[i]
    keep = [k for k in range(len(points)) if k != i]
    new_labels = [merged if k == (i - 1) % len(points) else labels[k] for k in keep]
    return drop_spikes([points[k] for k in keep], new_labels, min_angle)


def kept_boundary_vertices(pts: np.ndarray, labels: list[str], min_edge: float) -> list[int]:
    """Indices of the boundary loop ``pts`` that a remesh keeps (see ``remesh``).

    ``labels[i]`` is the label of the edge leaving vertex i. Bed/wall corners and the
    contact points of the surface are always kept.
    """
    before, after = pts - np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0) - pts
    turn = np.degrees(np.abs(np.arctan2(
        before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0],
        np.sum(before * after, axis=1))))
    keep: list[int] = []
    dropped_previous = False
    for i in range(len(pts)):
        straight_run = labels[i - 1] == labels[i] and (
            labels[i] in (WALL, END, GATE)
            or (labels[i] == BED and turn[i] < CORNER_DEG))   # a bed profile's corner stays
        inner_surface = labels[i - 1] == labels[i] == SURFACE
        flat = inner_surface and turn[i] < STRAIGHT_DEG
        close = inner_surface and bool(keep) and (
            np.linalg.norm(pts[i] - pts[keep[-1]]) < min_edge
            or np.linalg.norm(pts[i] - pts[_next_fixed(labels, i)]) < min_edge)
        if straight_run or close or (flat and not dropped_previous):  # never two flat in a row
            dropped_previous = flat
            continue
        dropped_previous = False
        keep.append(i)
    return keep


def _next_fixed(labels: list[str], i: int) -> int:
    """The next vertex after i that is not an inner surface vertex (a contact point)."""
    n = len(labels)
    j = (i + 1) % n
    while labels[j - 1] == labels[j] == SURFACE and j != i:
        j = (j + 1) % n
    return j
