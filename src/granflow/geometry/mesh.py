"""Meshes of the domains (labels, ``geometry/labels.py``: ``bed``, ``wall``, ``surface``,
``end``, the far end of an erodible layer, and ``gate``)."""

from __future__ import annotations

from collections.abc import Sequence

import ngsolve as ngs
import numpy as np
from netgen.geom2d import SplineGeometry
from netgen.meshing import Element1D, Element2D, MeshingParameters, MeshPoint, NgException, Pnt
from netgen.meshing import Mesh as NgMesh
from ngsolve.meshes import MakeStructured2DMesh

from granflow.geometry.labels import BED, END, GATE, INTERIOR, LABELS, SURFACE, WALL
from granflow.geometry.profile import CORNER_DEG
from granflow.geometry.stretch import ISOTROPIC, LayerStretch

# what meshing a moved domain raises when it cannot be meshed (the time loop goes on after
# these: ``Simulation.mesher_failures``): Netgen's NgException (its meshers and OCC's
# lofting) and RuntimeError, which the remesh's geometry checks raise (a boundary that is
# not one loop, a fold not untangled, a triangle inverted by the layer's stretch; the loop's
# ``MeshingFailed`` is one) and pybind11 makes of the meshers' other C++ errors
MESHER_FAILURES: tuple[type[Exception], ...] = (NgException, RuntimeError)

__all__ = ["BED", "END", "GATE", "INTERIOR", "LABELS", "SURFACE", "WALL", "build_mesh",
           "periodic_layer_mesh", "polygon_mesh", "signed_areas", "stacked_layer_mesh",
           "triangle_quality"]

FLAT_QUALITY = 1e-6   # a fresh triangle of lower shape quality is flat (a sharp tip: 1e-3)


def periodic_layer_mesh(length: float, height: float, size: float,
                        cells_x: int | None = None) -> ngs.Mesh:
    """Structured triangles of [0, length] x [0, height], periodic in x (configuration (a)).

    ``cells_x`` defaults to round(length / size); the vertical cell size is exactly
    height / round(height / size).
    """
    ny = max(1, round(height / size))
    nx = cells_x if cells_x is not None else max(2, round(length / size))
    mesh = MakeStructured2DMesh(quads=False, nx=nx, ny=ny, periodic_x=True,
                                mapping=lambda x, y: (length * x, height * y))
    names = mesh.GetBoundaries()
    mesh.ngmesh.SetBCName(names.index("bottom"), BED)
    mesh.ngmesh.SetBCName(names.index("top"), SURFACE)
    return ngs.Mesh(mesh.ngmesh)


def stacked_layer_mesh(length: float, layers: Sequence[tuple[float, int]],
                       cells_x: int) -> ngs.Mesh:
    """Structured triangles of [0, length] x [0, sum of thicknesses], periodic in x, from
    the bed up: ``layers`` holds (thickness, cells across it), each layer's cells of equal
    height, so that a horizontal mesh line separates consecutive layers (a slab over a
    layer at rest)."""
    levels = [0.0]
    for thickness, cells in layers:
        levels += list(levels[-1] + thickness * np.arange(1, cells + 1) / cells)
    z = np.array(levels)
    unit = np.linspace(0.0, 1.0, len(z))
    mesh = MakeStructured2DMesh(quads=False, nx=cells_x, ny=len(z) - 1, periodic_x=True,
                                mapping=lambda x, y: (length * x, float(np.interp(y, unit, z))))
    names = mesh.GetBoundaries()
    mesh.ngmesh.SetBCName(names.index("bottom"), BED)
    mesh.ngmesh.SetBCName(names.index("top"), SURFACE)
    return ngs.Mesh(mesh.ngmesh)


def signed_areas(mesh: ngs.Mesh, coords: np.ndarray | None = None) -> np.ndarray:
    """Signed areas of all triangles (positive = not inverted) for given vertex positions."""
    xy = mesh.ngmesh.Coordinates() if coords is None else coords
    tri = mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1
    a, b, c = xy[tri[:, 0]], xy[tri[:, 1]], xy[tri[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def polygon_mesh(points: Sequence[tuple[float, float]], labels: Sequence[str],
                 size: float, edge_sizes: Sequence[float] | None = None,
                 interior: Sequence[tuple[int, int, float]] = (),
                 stretch: LayerStretch = ISOTROPIC,
                 restrict: np.ndarray | None = None) -> ngs.Mesh:
    """Netgen triangulation of a labelled polygon, without corner triangles.

    ``edge_sizes[i]`` (default ``size``) is the target length on edge i, from which Netgen
    grades the interior (a thin erodible layer is resolved this way). ``interior`` lists
    lines (point i, point j, edge length) the triangles must not cross (the initial
    interface of two materials). A triangle with two boundary edges flattens when the
    overturning front lands on the bed; such corner triangles are removed by flipping
    their interior edge. With ``stretch``, the polygon is meshed in its stretched
    coordinates (``geometry/stretch.py``), where sizes are given, and mapped back: cells
    along a thin layer come out long and flat. ``restrict`` (k, 3) holds points (x, z) and
    the largest edge h there (in the stretched coordinates), Netgen's local mesh-size
    restrictions (``MeshingParameters.RestrictH``), from which it grades the rest.
    """
    geo = SplineGeometry()
    split, edge = stretch.split(np.asarray(points, dtype=float))
    if len(split) > len(points):   # an edge crossing the layer's top: split there
        labels = [labels[k] for k in edge]
        edge_sizes = None if edge_sizes is None else [edge_sizes[k] for k in edge]
        renumber = {int(k): int(np.flatnonzero(edge == k)[0]) for k in np.unique(edge)}
        interior = [(renumber[i], renumber[j], h) for i, j, h in interior]
    mapped = stretch.forward(split)
    ids = [geo.AppendPoint(float(x), float(y)) for x, y in mapped]
    for i, label in enumerate(labels):
        local = {} if edge_sizes is None else {"maxh": min(size, edge_sizes[i])}
        geo.Append(["line", ids[i], ids[(i + 1) % len(ids)]], bc=label,
                   leftdomain=1, rightdomain=0, **local)
    for i, j, h in interior:
        geo.Append(["line", ids[i], ids[j]], bc=INTERIOR, leftdomain=1, rightdomain=1,
                   maxh=min(size, h))
    if restrict is None or not len(restrict):
        ngmesh = geo.GenerateMesh(maxh=size)
    else:
        parameters = MeshingParameters(maxh=size)
        at = stretch.forward(np.asarray(restrict, dtype=float)[:, :2])
        for (x, y), h in zip(at, np.asarray(restrict)[:, 2], strict=True):
            parameters.RestrictH(float(x), float(y), 0.0, float(h))
        ngmesh = geo.GenerateMesh(mp=parameters)
    xy = np.array([[p[0], p[1]] for p in ngmesh.Points()])
    tri = ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1
    seg = ngmesh.Elements1D().NumPy()
    seg_labels = [ngmesh.GetBCName(int(i) - 1) for i in seg["index"]]
    boundary = np.array([lab != INTERIOR for lab in seg_labels], dtype=bool)
    segments = seg["nodes"][boundary, :2].astype(np.int64) - 1
    seg_labels = [lab for lab in seg_labels if lab != INTERIOR]
    tri = flip_flat_triangles(xy, flip_corner_triangles(xy, tri))
    xy, tri, segments, seg_labels = collapse_flat_corners(xy, tri, segments, seg_labels)
    if not stretch.identity:
        xy = stretch.inverse(xy)
        p = xy[tri]
        e = np.roll(p, -1, axis=1) - p
        if np.any(e[:, 0, 0] * e[:, 1, 1] - e[:, 0, 1] * e[:, 1, 0] <= 0):
            raise RuntimeError("a triangle inverted when mapped back from the stretched "
                               "layer's coordinates; try a smaller mesh.layer_aspect")
    return build_mesh(xy, tri, segments, seg_labels)


def build_mesh(xy: np.ndarray, tri: np.ndarray, segments: np.ndarray,
               seg_labels: Sequence[str]) -> ngs.Mesh:
    """An NGSolve mesh from vertices, triangles and labelled boundary segments."""
    ngmesh = NgMesh(dim=2)
    pids = [ngmesh.Add(MeshPoint(Pnt(float(x), float(y), 0.0))) for x, y in xy]
    domain = ngmesh.AddRegion("material", dim=2)
    for a, b, c in tri:
        ngmesh.Add(Element2D(domain, [pids[a], pids[b], pids[c]]))
    regions: dict[str, int] = {}
    for name in LABELS:
        regions[name] = ngmesh.AddRegion(name, dim=1)
    for (a, b), name in zip(segments, seg_labels, strict=True):
        ngmesh.Add(Element1D([pids[a], pids[b]], index=regions[name]))
    return ngs.Mesh(ngmesh)


def boundary_edge_counts(tri: np.ndarray) -> np.ndarray:
    """Number of boundary edges of each triangle."""
    edges = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    _, inverse, counts = np.unique(edges, axis=0, return_inverse=True, return_counts=True)
    on_boundary = (counts[inverse.ravel()] == 1).reshape(3, -1)
    return on_boundary.sum(axis=0)


def flip_corner_triangles(xy: np.ndarray, tri: np.ndarray, max_passes: int = 5) -> np.ndarray:
    """Flip the interior edge of every triangle that has two boundary edges, when convex."""
    tri = tri.copy()
    for _ in range(max_passes):
        corner = np.flatnonzero(boundary_edge_counts(tri) >= 2)
        if corner.size == 0:
            break
        for t in corner:
            _flip_interior_edge(xy, tri, t)
    return tri


def flip_flat_triangles(xy: np.ndarray, tri: np.ndarray,
                        min_quality: float = FLAT_QUALITY) -> np.ndarray:
    """Flip the long edge of every flat triangle (three vertices in a line), when convex.

    Netgen can close a thin overturning nose with a triangle whose three vertices are
    boundary vertices in a line (a surface vertex lying on the chord from the underside to
    the tip): its area is round-off, so the next move of any size inverts it, and every
    remesh of that boundary made it again (a run's steps fell to 1e-14 s). Flipping the
    edge opposite the straight angle triangulates the same polygon without it.
    """
    tri = tri.copy()
    for t in np.flatnonzero(triangle_quality(xy, tri) < min_quality):
        _flip_interior_edge(xy, tri, int(t))
    return tri


def triangle_quality(xy: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """4 sqrt(3) area / (sum of squared edge lengths): 1 equilateral, 0 flat or inverted."""
    p = xy[tri]
    e = np.roll(p, -1, axis=1) - p
    area = 0.5 * (e[:, 0, 0] * e[:, 1, 1] - e[:, 0, 1] * e[:, 1, 0])
    return 4.0 * np.sqrt(3.0) * area / np.sum(e**2, axis=(1, 2))


def collapse_flat_corners(xy: np.ndarray, tri: np.ndarray, segments: np.ndarray,
                          labels: Sequence[str], min_quality: float = 0.05
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]]:
    """Remove flat triangles with two boundary edges of one label that no flip could fix.

    Their middle vertex lies (almost) on the chord of its neighbours, so the convex flip is
    impossible; dropping that vertex and the sliver replaces two boundary edges by the
    chord (the area change is a sliver's; the column's area correction restores it). A bed
    vertex where the bed turns (a corner of a bed profile) is never dropped.
    """
    labels = list(labels)
    for _ in range(10):
        counts = boundary_edge_counts(tri)
        quality = triangle_quality(xy, tri)
        bad = [t for t in np.flatnonzero((counts >= 2) & (quality < min_quality))]
        done = False
        for t in bad:
            for m in tri[t]:
                ends = [k for k in range(len(segments)) if m in segments[k]]
                if len(ends) != 2 or labels[ends[0]] != labels[ends[1]]:
                    continue
                k_in = ends[0] if segments[ends[0]][1] == m else ends[1]
                k_out = ends[1] if k_in == ends[0] else ends[0]
                a, b = segments[k_in][0], segments[k_out][1]
                if set(tri[t]) != {a, m, b} or (labels[k_in] == BED
                                                and _turn_deg(xy[a], xy[m], xy[b]) > CORNER_DEG):
                    continue
                segments = segments.copy()
                segments[k_in] = [a, b]
                keep_seg = np.arange(len(segments)) != k_out
                segments = segments[keep_seg]
                labels = [lab for k, lab in enumerate(labels) if keep_seg[k]]
                tri = np.delete(tri, t, axis=0)
                xy = np.delete(xy, m, axis=0)
                tri = tri - (tri > m)
                segments = segments - (segments > m)
                done = True
                break
            if done:
                break
        if not done:
            break
    return xy, tri, segments, labels


def _flip_interior_edge(xy: np.ndarray, tri: np.ndarray, t: int) -> None:
    a, b, c = tri[t]
    for p, q, r in ((a, b, c), (b, c, a), (c, a, b)):
        # edge (p, q), opposite vertex r; find the neighbour across (p, q)
        shares_p = np.any(tri == p, axis=1)
        shares_q = np.any(tri == q, axis=1)
        neighbours = np.flatnonzero(shares_p & shares_q)
        neighbours = neighbours[neighbours != t]
        if neighbours.size != 1:
            continue
        n = neighbours[0]
        d = next(int(v) for v in tri[n] if v not in (p, q))
        new1, new2 = np.array([r, p, d]), np.array([r, d, q])
        if _area(xy, new1) > 0 and _area(xy, new2) > 0:
            tri[t], tri[n] = new1, new2
            return


def _turn_deg(a: np.ndarray, m: np.ndarray, b: np.ndarray) -> float:
    """How far the polyline a, m, b turns at m (degrees)."""
    u, v = m - a, b - m
    return float(np.degrees(abs(np.arctan2(u[0] * v[1] - u[1] * v[0], u @ v))))


def _area(xy: np.ndarray, t: np.ndarray) -> float:
    (x0, y0), (x1, y1), (x2, y2) = xy[t[0]], xy[t[1]], xy[t[2]]
    return 0.5 * ((x1 - x0) * (y2 - y0) - (y1 - y0) * (x2 - x0))
