"""A mesh-size field from the flow: fine where the material moves, coarse where it rests.

A collapse over an erodible layer needs the layer's thin cells only where the layer is
sheared or about to be: under and just ahead of the moving material. Under the deposit
at rest, under the column's static wedge and far ahead of the front the layer rests, and
its cells may be ``layer_coarse`` long along the bed. The column's own cells may grow from
``fine`` (mesh.size) to ``coarse`` where it rests. The field is handed to Netgen as local
mesh-size restrictions (``MeshingParameters.RestrictH`` at points, ``geometry/mesh.py``)
and as the boundary edges' sizes; Netgen grades the sizes between them smoothly (its
``grading``). Sizes in the erodible layer are in the coordinates the mesh is made in
(``geometry/stretch.py``: ``layer_fine`` is ``layer_aspect`` times the cells' thickness).

Where the flow goes next is read from where it is: the layer is fine (``windows``, intervals
of x) within ``margin`` of material moving near it, and the bulk within ``margin`` of moving
material (``moving``, their points). ``uncovered`` tells the remesher when moving material
has come within half the margin of coarse cells, so that the mesh is refined before the flow
reaches them, and ``overgrown`` when much of the fine mesh has come to rest, so that it is
coarsened (a deposit at rest never degrades the mesh, which is what otherwise remeshes).
The field is plain data (``state``, ``from_state``): a checkpoint keeps it, so a resumed
run knows where its mesh is fine.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

Heights = Callable[[np.ndarray], np.ndarray]   # height above the bed of points (n, 2)
BedLevel = Callable[[np.ndarray], np.ndarray]  # the bed's z at abscissae x (n,)
ON_BED = 1e-6   # relative to h_e: an edge whose ends are this close to the bed lies on it
LEAD = 2.0      # margins the fine layer reaches ahead of the furthest moving material
IDLE_MARGINS = 4.0   # margins of the fine layer at rest that call for a coarser mesh


@dataclass(frozen=True)
class SizeField:
    """Target edge lengths: ``fine`` and ``coarse`` for the bulk, ``layer_fine`` and
    ``layer_coarse`` (meshing coordinates) for an erodible layer ``layer_top`` thick
    (0: a rigid bed), fine within ``windows`` (k, 2) along x and around ``moving`` (m, 2)."""

    fine: float
    coarse: float
    layer_fine: float = 0.0
    layer_coarse: float = 0.0
    layer_top: float = 0.0
    margin: float = 0.0
    windows: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    moving: np.ndarray | None = None   # None: the bulk is fine everywhere

    @property
    def maxh(self) -> float:
        """The largest edge anywhere (Netgen's global maxh)."""
        sizes = [self.fine, self.coarse if self.moving is not None else self.fine]
        return max(sizes + ([self.layer_coarse] if self.layer_top > 0 else []))

    def in_windows(self, x: np.ndarray, shrink: float = 0.0) -> np.ndarray:
        """Whether each abscissa lies in a window of the fine layer (shrunk by ``shrink``
        at both ends)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        w = self.windows
        if not len(w):
            return np.zeros(x.shape, dtype=bool)
        return np.any((x[:, None] >= w[:, 0] + shrink) & (x[:, None] <= w[:, 1] - shrink),
                      axis=1)

    def edge_size(self, heights: Heights) -> Callable[[np.ndarray, np.ndarray], float]:
        """The target length of the boundary edge from p to q. In the layer (both ends
        within 2 h_e of the bed): an edge on the bed ``layer_coarse`` (a straight run of bed
        is one edge from the wall to the layer's end: the restrictions refine it in the
        windows), any other (the layer's free top, its end) ``layer_fine`` where it meets a
        window, else ``layer_coarse``. Elsewhere the bulk's ``coarse`` (the restrictions
        refine it around moving material)."""
        he = self.layer_top
        bulk = self.coarse if self.moving is not None else self.fine

        def size(p: np.ndarray, q: np.ndarray) -> float:
            height = heights(np.array([p, q]))
            if he <= 0 or height.max() > 2 * he:
                return bulk
            if height.max() <= ON_BED * he:
                return self.layer_coarse
            lo, hi = min(p[0], q[0]), max(p[0], q[0])
            meets = any(lo <= b and hi >= a for a, b in self.windows)
            return self.layer_fine if meets else self.layer_coarse
        return size

    def restrictions(self, bed: BedLevel) -> np.ndarray:
        """Points (x, z, h) where the mesh must be at most h: the bed every half fine cell
        along each window (Netgen grades the layer above it as it grades from a fine edge),
        and the moving material's points."""
        out = []
        if self.layer_top > 0:
            step = 0.5 * self.layer_fine
            for a, b in self.windows:
                x = np.linspace(a, b, max(2, int(np.ceil((b - a) / step)) + 1))
                out.append(np.column_stack([x, bed(x), np.full_like(x, self.layer_fine)]))
        if self.moving is not None and self.coarse > self.fine and len(self.moving):
            out.append(np.column_stack([self.moving, np.full(len(self.moving), self.fine)]))
        return np.concatenate(out) if out else np.zeros((0, 3))

    def uncovered(self, moving: np.ndarray, heights: Heights, end_x: float) -> bool:
        """Whether material moving at ``moving`` (m, 2) has come within half the margin of
        coarse cells: of the layer at rest (points within the margin above the layer, whose
        meshed part ends at ``end_x``), or of the bulk at rest."""
        if not len(moving):
            return False
        if self.layer_top > 0:       # (the layer's ends, x = 0 and end_x, need no margin)
            half = 0.5 * self.margin
            near = moving[heights(moving) <= self.layer_top + self.margin, 0]
            x = np.clip(near, half, max(half, end_x - half))
            if len(near) and not self.in_windows(x, half).all():
                return True
        if self.moving is None or self.coarse <= self.fine:
            return False
        if not len(self.moving):
            return True
        distance, _ = cKDTree(self.moving).query(moving)
        return bool(distance.max() > 0.5 * self.margin)

    def overgrown(self, moving: np.ndarray, heights: Heights, end_x: float) -> bool:
        """Whether much of the fine mesh now lies where the material rests: IDLE_MARGINS
        margins of the layer's windows (and at least half of them) away from material moving
        near it (so the windows about a creeping front, two margins and the lead long, never
        count), or half the bulk's fine points beyond the margin of moving material."""
        if self.layer_top > 0 and len(self.windows):
            near = moving[heights(moving) <= self.layer_top + self.margin]
            needed = layer_windows(near, self.margin, 0.0, end_x)
            fine = float(np.sum(self.windows[:, 1] - self.windows[:, 0]))
            idle = fine - overlap(self.windows, needed)
            if idle >= max(IDLE_MARGINS * self.margin, 0.5 * fine):
                return True
        if self.moving is None or self.coarse <= self.fine or not len(self.moving):
            return False
        if not len(moving):
            return True
        distance, _ = cKDTree(moving).query(self.moving)
        return bool(np.mean(distance > self.margin) > 0.5)

    def state(self) -> dict[str, object]:
        """Plain data for a checkpoint."""
        return {"windows": np.asarray(self.windows, dtype=float),
                "moving": (np.zeros((0, 2)) if self.moving is None
                           else np.asarray(self.moving, dtype=float)),
                "bulk_fine_everywhere": self.moving is None}

    def from_state(self, state: dict[str, object]) -> SizeField:
        """This field's sizes with the windows and moving points of ``state``."""
        windows = np.asarray(state["windows"], dtype=float).reshape(-1, 2)
        moving = None if state["bulk_fine_everywhere"] else (
            np.asarray(state["moving"], dtype=float).reshape(-1, 2))
        return SizeField(self.fine, self.coarse, self.layer_fine, self.layer_coarse,
                         self.layer_top, self.margin, windows, moving)


def layer_windows(points: np.ndarray, margin: float, lo: float, hi: float) -> np.ndarray:
    """The union of [x - margin, x + margin] over the abscissae of ``points``, clipped to
    [lo, hi], as sorted disjoint intervals (k, 2)."""
    if not len(points):
        return np.zeros((0, 2))
    x = np.sort(np.asarray(points, dtype=float)[:, 0])
    starts, ends = np.maximum(x - margin, lo), np.minimum(x + margin, hi)
    merged: list[list[float]] = []
    for a, b in zip(starts, ends, strict=True):
        if a > b:
            continue
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
        else:
            merged.append([a, b])
    return np.array(merged).reshape(-1, 2)


def overlap(a: np.ndarray, b: np.ndarray) -> float:
    """Total length of the intersection of two sets of disjoint intervals (k, 2)."""
    total = 0.0
    for lo, hi in a:
        total += float(np.sum(np.clip(np.minimum(hi, b[:, 1]) - np.maximum(lo, b[:, 0]), 0,
                                      None)))
    return total


def flow_size_field(base: SizeField, xy: np.ndarray, moving: np.ndarray, heights: Heights,
                    end_x: float) -> SizeField:
    """``base``'s sizes refitted to the flow: vertices ``xy`` (n, 2) with ``moving`` (n,)
    flags. The layer is fine within the margin of moving vertices less than the margin
    above it, and LEAD margins ahead of the furthest (the layer beyond its meshed end
    ``end_x`` does not exist); the bulk around every moving vertex."""
    points = xy[moving]
    near = points[heights(points) <= base.layer_top + base.margin] if base.layer_top > 0 else (
        np.zeros((0, 2)))
    windows = layer_windows(near, base.margin, 0.0, end_x)
    if len(windows):             # the flow goes on along the bed: fine further ahead of it
        windows[-1, 1] = min(end_x, near[:, 0].max() + LEAD * base.margin)
    return SizeField(base.fine, base.coarse, base.layer_fine, base.layer_coarse,
                     base.layer_top, base.margin, windows, points.copy())
