"""Many points located in a moving mesh at once, and fields evaluated there.

A material point tracked through the flow (an erodible layer's line and markers) lies, step
after step, in the triangle it lay in before or in a neighbour of it. ``PointLocator``
builds the triangles' neighbours once per mesh (the ALE moves the vertices, never the
connectivity) and walks, for all points together with numpy, from a first guess (the
triangle the point was in at the last call, else the one whose centroid is nearest: from
a k-d tree of the current centroids, or for a few points their distances to every one)
across the edge facing the point until the point's barycentric coordinates are all
non-negative. A point whose walk leaves the mesh is
outside if it is outside the boundary polygon by more than the tolerance, else (behind a
concave stretch of the boundary, or on it) tested against every triangle. A point is
inside when it is within NGSolve's own tolerance of a triangle (barycentric coordinates
above -1e-6), as NGSolve's search decides; that search rebuilds its tree whenever the
vertices have moved (about 5 ms for a thousand triangles and 4,500 points, every step).
The fields are then evaluated by NGSolve on one array of mesh points (its compiled
evaluation), sorted by triangle (half the time of the points' own order, the same values).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import shapely
from scipy.spatial import cKDTree

from granflow.fem.sampling import triangles
from granflow.simulation.outcomes import MeshingFailed

WALK_STEPS = 16     # triangles crossed at most before a point is tested against all
TOLERANCE = 1e-6    # NGSolve's: a point with barycentric coordinates above -TOLERANCE is in
CHUNK = 2_000_000   # point-triangle pairs tested at once by the exhaustive search
FEW_PAIRS = 50_000  # point-site pairs under which the nearest site is found without a tree


def neighbours(tri: np.ndarray) -> np.ndarray:
    """(ne, 3): the triangle across the edge opposite each corner, -1 on the boundary."""
    ne = len(tri)
    edges = np.stack([tri[:, [1, 2]], tri[:, [2, 0]], tri[:, [0, 1]]], axis=1).reshape(-1, 2)
    key = np.sort(edges, axis=1)
    code = key[:, 0] * (int(tri.max()) + 1) + key[:, 1]
    order = np.argsort(code, kind="stable")
    same = np.flatnonzero(code[order][1:] == code[order][:-1])
    out = np.full(3 * ne, -1, dtype=np.int64)
    a, b = order[same], order[same + 1]
    out[a], out[b] = b // 3, a // 3
    return out.reshape(ne, 3)


class PointLocator:
    """Locates points in ``mesh`` (its vertices may move between calls) and evaluates
    coefficient functions there (module docstring)."""

    def __init__(self, mesh: ngs.Mesh) -> None:
        self.mesh = mesh
        self.tri = triangles(mesh)
        self.across = neighbours(self.tri)
        probe = self.tri[0]
        xy = mesh.ngmesh.Coordinates()
        centre = xy[probe].mean(axis=0)
        template = mesh(np.array([centre[0]]), np.array([centre[1]]))
        self._dtype, self._meshptr = template.dtype, template["meshptr"][0]
        self.loop = _boundary_loop(mesh)
        self.searched = 0     # points tested against every triangle (the walk's misses)
        self._owners: tuple[np.ndarray, np.ndarray] | None = None   # (``at_vertices``)

    def locate(self, points: np.ndarray, guess: np.ndarray | None = None
               ) -> tuple[np.ndarray, np.ndarray]:
        """Per point, its triangle (-1 outside the mesh) and its first two barycentric
        coordinates there (NGSolve's reference coordinates of the triangle). ``guess``:
        a triangle near each point (the last call's answer for the same points), where
        the walk starts; -1 or None: the triangle with the nearest centroid."""
        xy = self.mesh.ngmesh.Coordinates()
        corners = xy[self.tri]
        n = len(points)
        element = np.full(n, -1, dtype=np.int64)
        lam = np.zeros((n, 2))
        if n == 0:
            return element, lam
        current = (np.full(n, -1, dtype=np.int64) if guess is None or len(guess) != n
                   else np.asarray(guess, dtype=np.int64).copy())
        fresh = current < 0
        if fresh.any():
            current[fresh] = nearest(corners.mean(axis=1), points[fresh])
        frames = _Frames(corners)
        todo, px, py = np.arange(n), points[:, 0].copy(), points[:, 1].copy()
        for _ in range(WALK_STEPS):
            l0, l1, l2 = frames.barycentric(current, px, py)
            lowest, corner = _lowest(l0, l1, l2)
            step = self.across[current, corner]
            found = (lowest >= 0.0) | ((step < 0) & (lowest >= -TOLERANCE))
            at = todo[found]
            element[at] = current[found]
            lam[at, 0], lam[at, 1] = l0[found], l1[found]
            go = ~found & (step >= 0)
            todo, current, px, py = todo[go], step[go], px[go], py[go]
            if not len(todo):
                break
        missed = np.flatnonzero(element < 0)
        if len(missed):       # outside, unless behind a concave stretch of the boundary
            edges = np.hypot(*(corners - np.roll(corners, 1, axis=1)).transpose(2, 0, 1))
            missed = missed[self._near_boundary(xy, points[missed],   # or on it, within
                                                TOLERANCE * float(edges.max()))]  # the tolerance
        if len(missed):
            self.searched += len(missed)
            element[missed], lam[missed] = self._search(corners, points[missed])
        return element, lam

    def _near_boundary(self, xy: np.ndarray, points: np.ndarray, distance: float
                       ) -> np.ndarray:
        """Which ``points`` lie within ``distance`` of the mesh's boundary polygon. A
        boundary too degenerate for shapely (fewer than three vertices, a topology GEOS
        rejects) is the mesher's failure, not a defect (``MeshingFailed``)."""
        try:
            polygon = shapely.Polygon(xy[self.loop])
            return shapely.dwithin(polygon, shapely.points(points), distance)
        except (ValueError, shapely.errors.GEOSException) as exc:
            raise MeshingFailed(f"the mesh's boundary is not a polygon: {exc}") from exc

    def _search(self, corners: np.ndarray, points: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
        """Points tested against every triangle: the one they are in, else the one they
        are nearest to within the tolerance, else -1."""
        element = np.full(len(points), -1, dtype=np.int64)
        lam = np.zeros((len(points), 2))
        rows = max(1, CHUNK // len(corners))
        for start in range(0, len(points), rows):
            p = points[start:start + rows]
            coords = _barycentric(np.broadcast_to(corners, (len(p), *corners.shape)),
                                  p[:, None, :])
            lowest = np.nan_to_num(coords.min(axis=2), nan=-np.inf)   # a flat triangle
            best = np.argmax(lowest, axis=1)
            ok = lowest[np.arange(len(p)), best] >= -TOLERANCE
            element[start:start + rows] = np.where(ok, best, -1)
            lam[start:start + rows] = np.where(ok[:, None],
                                               coords[np.arange(len(p)), best, :2], 0.0)
        return element, lam

    def mesh_points(self, element: np.ndarray, lam: np.ndarray) -> np.ndarray:
        """NGSolve's array of mesh points for located points (all inside)."""
        out = np.zeros(len(element), dtype=self._dtype)
        out["x"], out["y"] = lam[:, 0], lam[:, 1]
        out["meshptr"], out["nr"], out["facetnr"] = self._meshptr, element, -1
        return out

    def values(self, cf: ngs.CoefficientFunction, points: np.ndarray) -> np.ndarray:
        """``cf`` at the points (n, 2), shape (n, cf.dim) (``evaluate``)."""
        return self.evaluate(cf, points, *self.locate(points))

    def evaluate(self, cf: ngs.CoefficientFunction, points: np.ndarray, element: np.ndarray,
                 lam: np.ndarray) -> np.ndarray:
        """``cf`` at the points located by ``locate``, shape (n, cf.dim). A point a hair
        outside the moved mesh (a tracked material point on the free surface, which the ALE
        follows to first order) takes the value at the nearest vertex (read in one
        triangle around it)."""
        out = np.empty((len(points), cf.dim))
        inside = element >= 0
        if inside.any():        # triangle by triangle: NGSolve reads each one's dofs once
            order = np.flatnonzero(inside)
            order = order[np.argsort(element[order], kind="stable")]
            found = self.mesh_points(element[order], lam[order])
            out[order] = np.asarray(cf(found)).reshape(-1, cf.dim)
        if not inside.all():
            xy = self.mesh.ngmesh.Coordinates()
            out[~inside] = self.at_vertices(cf, nearest(xy, points[~inside]))
        return out

    def at_vertices(self, cf: ngs.CoefficientFunction, vertices: np.ndarray) -> np.ndarray:
        """``cf`` at mesh vertices, each read in one triangle that has it as a corner."""
        if self._owners is None:     # once per mesh: the connectivity does not change
            owner = np.full(self.mesh.nv, -1, dtype=np.int64)
            corner = np.zeros(self.mesh.nv, dtype=np.int64)
            for k in (2, 1, 0):      # any triangle will do; the lowest corner number wins
                owner[self.tri[:, k]] = np.arange(len(self.tri))
                corner[self.tri[:, k]] = k
            self._owners = owner, corner
        owner, corner = self._owners
        lam = np.zeros((len(vertices), 2))
        which = corner[vertices]
        lam[which == 0, 0] = 1.0
        lam[which == 1, 1] = 1.0
        found = self.mesh_points(owner[vertices], lam)
        return np.asarray(cf(found)).reshape(-1, cf.dim)


def nearest(sites: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Per point, the index of the nearest site: by a k-d tree, or for a few points (the
    walk's misses a step leaves, a tree not worth building) by their squared distances to
    every site, the sums the tree compares."""
    if len(points) * len(sites) > FEW_PAIRS:
        return cKDTree(sites).query(points)[1]
    d = sites[None, :, :] - points[:, None, :]
    return np.argmin(d[..., 0] * d[..., 0] + d[..., 1] * d[..., 1], axis=1)


def _boundary_loop(mesh: ngs.Mesh) -> np.ndarray:
    """The boundary's vertices in order around it (the mesh has one boundary loop)."""
    segments = mesh.ngmesh.Elements1D().NumPy()["nodes"][:, :2].astype(np.int64) - 1
    after = dict(segments.tolist())
    loop = [int(segments[0, 0])]
    while len(loop) <= len(segments):
        nxt = after[loop[-1]]
        if nxt == loop[0]:
            break
        loop.append(nxt)
    return np.array(loop, dtype=np.int64)


class _Frames:
    """Per triangle, the terms ``_barycentric`` computes its coordinates from, as flat
    arrays (the same numbers, gathered per point faster than the corners)."""

    def __init__(self, corners: np.ndarray) -> None:
        c = np.ascontiguousarray(corners.transpose(2, 1, 0))     # (x/y, corner, triangle)
        self.ox, self.oy = c[0, 2], c[1, 2]
        self.ax, self.ay = c[0, 0] - self.ox, c[1, 0] - self.oy
        self.bx, self.by = c[0, 1] - self.ox, c[1, 1] - self.oy
        self.det = self.ax * self.by - self.ay * self.bx

    def barycentric(self, element: np.ndarray, px: np.ndarray, py: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The three barycentric coordinates of the points (px, py) in their triangles."""
        rx, ry = px - self.ox[element], py - self.oy[element]
        ax, ay, bx, by = (self.ax[element], self.ay[element], self.bx[element],
                          self.by[element])
        det = self.det[element]
        l0 = (rx * by - ry * bx) / det
        l1 = (ax * ry - ay * rx) / det
        return l0, l1, 1.0 - l0 - l1


def _lowest(l0: np.ndarray, l1: np.ndarray, l2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The smallest of three coordinates and which one (the first of equals, as argmin;
    a NaN of a flat triangle is the smallest)."""
    lowest = np.minimum(np.minimum(l0, l1), l2)
    corner = np.where(l0 == lowest, 0, np.where(l1 == lowest, 1, 2))
    flat = np.isnan(lowest)
    if flat.any():
        corner[flat] = np.argmin(np.stack([l0[flat], l1[flat], l2[flat]], axis=1), axis=1)
    return lowest, corner


def _barycentric(c: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (..., 3) of points p (..., 2) in triangles c (..., 3, 2)."""
    a, b = c[..., 0, :] - c[..., 2, :], c[..., 1, :] - c[..., 2, :]
    r = p - c[..., 2, :]
    det = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    l0 = (r[..., 0] * b[..., 1] - r[..., 1] * b[..., 0]) / det
    l1 = (a[..., 0] * r[..., 1] - a[..., 1] * r[..., 0]) / det
    return np.stack([l0, l1, 1.0 - l0 - l1], axis=-1)
