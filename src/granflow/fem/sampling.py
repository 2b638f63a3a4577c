"""Fields sampled to numpy: at vertices, as cell means, along lines."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np


def triangles(mesh: ngs.Mesh) -> np.ndarray:
    """(ne, 3) zero-based vertex indices of the triangles."""
    return mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1


def vertex_samples(mesh: ngs.Mesh, cf: ngs.CoefficientFunction) -> np.ndarray:
    """Values of ``cf`` at every vertex, shape (nv,) or (nv, dim).

    Interpolated into continuous P1 (vertex values of continuous fields are exact; a
    discontinuous field gets a local average), so no point search on the moved mesh.
    """
    dim = cf.dim
    space = ngs.VectorH1(mesh, order=1) if dim > 1 else ngs.H1(mesh, order=1)
    field = ngs.GridFunction(space)
    field.Set(cf)
    nv = mesh.nv
    if dim > 1:
        return np.column_stack([c.vec.FV().NumPy()[:nv] for c in field.components])
    return field.vec.FV().NumPy()[:nv].copy()


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
