"""Fields sampled to numpy: at vertices, as cell means, along lines."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from scipy.spatial import cKDTree


def triangles(mesh: ngs.Mesh) -> np.ndarray:
    """(ne, 3) zero-based vertex indices of the triangles."""
    return mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1


def cells(mesh: ngs.Mesh) -> np.ndarray:
    """(ne, 3) zero-based vertex indices of the triangles, or (ne, 4) of the tetrahedra of a
    3D mesh."""
    if mesh.dim == 3:
        return mesh.ngmesh.Elements3D().NumPy()["nodes"][:, :4].astype(np.int64) - 1
    return triangles(mesh)


def vertex_samples(mesh: ngs.Mesh, cf: ngs.CoefficientFunction) -> np.ndarray:
    """Values of ``cf`` at every vertex, shape (nv,) or (nv, dim).

    Interpolated into continuous P1 through its dual basis, i.e. evaluated at the vertices
    (exact for continuous fields; a discontinuous one gets one adjacent element's value), so
    no point search on the moved mesh. (NGSolve's default ``Set`` is a local L2 projection,
    whose vertex values of a P2 velocity are off by a few percent of the speed.)
    """
    dim = cf.dim
    space = ngs.VectorH1(mesh, order=1) if dim > 1 else ngs.H1(mesh, order=1)
    field = ngs.GridFunction(space)
    field.Set(cf, dual=True)
    nv = mesh.nv
    if dim > 1:
        return np.column_stack([c.vec.FV().NumPy()[:nv] for c in field.components])
    return field.vec.FV().NumPy()[:nv].copy()


def values_at(mesh: ngs.Mesh, cf: ngs.CoefficientFunction, points: np.ndarray) -> np.ndarray:
    """``cf`` at the points (n, 2), shape (n, cf.dim). A point a hair outside the moved mesh
    (a tracked material point on the free surface, which the ALE follows to first order)
    takes the value at the nearest vertex."""
    mesh.ngmesh.Update()  # the point-search tree must follow the moved vertices
    found = mesh(points[:, 0], points[:, 1])
    inside = found["nr"] >= 0
    out = np.empty((len(points), cf.dim))
    if inside.any():
        out[inside] = np.asarray(cf(found[inside])).reshape(-1, cf.dim)
    if not inside.all():
        xy = mesh.ngmesh.Coordinates()
        nearest = cKDTree(xy).query(points[~inside])[1]
        at_vertices = np.column_stack([vertex_samples(mesh, cf[i]) for i in range(cf.dim)])
        out[~inside] = at_vertices[nearest]
    return out


def point_values(mesh: ngs.Mesh, cf: ngs.CoefficientFunction, x: float,
                 z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``cf`` along the vertical X = x at heights ``z``; points outside the mesh are dropped."""
    mesh.ngmesh.Update()  # the point-search tree must follow the moved vertices
    kept, values = [], []
    for zi in z:
        point = mesh(x, float(zi))
        if point.nr >= 0:
            kept.append(zi)
            values.append(cf(point))
    return np.asarray(kept), np.asarray(values)


def cell_means(mesh: ngs.Mesh, cf: ngs.CoefficientFunction) -> tuple[np.ndarray, np.ndarray]:
    """Mean of a scalar ``cf`` over each triangle, and the triangle areas."""
    areas = ngs.Integrate(ngs.CF(1.0), mesh, element_wise=True).NumPy().copy()
    totals = ngs.Integrate(cf, mesh, element_wise=True, order=4).NumPy().copy()
    return totals / areas, areas
