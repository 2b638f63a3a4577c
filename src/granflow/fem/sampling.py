"""Fields sampled to numpy: at vertices, as cell means, along lines."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np


def triangles(mesh: ngs.Mesh) -> np.ndarray:
    """(ne, 3) zero-based vertex indices of the triangles."""
    return mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1


def vertex_samples(mesh: ngs.Mesh, cf: ngs.CoefficientFunction) -> np.ndarray:
    """Values of ``cf`` at every vertex, shape (nv,) or (nv, dim)."""
    xy = mesh.ngmesh.Coordinates()
    values = np.asarray(cf(mesh(xy[:, 0].copy(), xy[:, 1].copy())))
    return values[:, 0] if values.ndim == 2 and values.shape[1] == 1 else values


def cell_means(mesh: ngs.Mesh, cf: ngs.CoefficientFunction) -> tuple[np.ndarray, np.ndarray]:
    """Mean of a scalar ``cf`` over each triangle, and the triangle areas."""
    areas = ngs.Integrate(ngs.CF(1.0), mesh, element_wise=True).NumPy().copy()
    totals = ngs.Integrate(cf, mesh, element_wise=True, order=4).NumPy().copy()
    return totals / areas, areas
