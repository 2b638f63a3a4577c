"""Field transfer across a remesh of a 3D column (``ale/transfer.py``'s, on tetrahedra):
the new mesh's vertices and edge midpoints located in the old mesh, each point outside it
(the new body's surface is lofted through sections of the old one, so a sliver may lie
outside) taken just inside the old tetrahedron at its nearest old vertex; the P2 velocity
set from those values and projected onto the discretely divergence-free fields."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from scipy.spatial import cKDTree

from granflow.ale.transfer import StateTransfer
from granflow.geometry.mesh3d import tetrahedra

NUDGE = 1e-6    # how far (relative) from an old vertex towards its tetrahedron's centre


def locate_3d(mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """NGSolve mesh points of ``points`` (n, 3), found in one vectorised call; the ``nr``
    field is -1 for a point outside the mesh."""
    return mesh(*(np.ascontiguousarray(points[:, k], dtype=float) for k in range(3)))


def inside(mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """The points, those outside ``mesh`` replaced by a point just inside a tetrahedron at
    their nearest vertex of it."""
    out = np.array(points, dtype=float)
    mesh.ngmesh.Update()  # the point-search tree must follow the moved vertices
    outside = np.flatnonzero(locate_3d(mesh, out)["nr"] < 0)
    if outside.size == 0:
        return out
    xyz = mesh.ngmesh.Coordinates()
    tets = tetrahedra(mesh)
    owner = np.empty(mesh.nv, dtype=np.int64)
    owner[tets.ravel()] = np.repeat(np.arange(len(tets)), 4)
    nearest = cKDTree(xyz).query(out[outside])[1]
    centre = xyz[tets[owner[nearest]]].mean(axis=1)
    out[outside] = xyz[nearest] + NUDGE * (centre - xyz[nearest])
    return out


class ChannelStateTransfer(StateTransfer):
    """``StateTransfer`` on tetrahedra (its divergence-free projection is the same)."""

    @staticmethod
    def _values(field: ngs.CoefficientFunction, mesh: ngs.Mesh,
                points: np.ndarray) -> np.ndarray:
        values = np.asarray(field(locate_3d(mesh, points)), dtype=float)
        return values.reshape(len(points), -1)

    def _clamped(self, old_mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
        if self._clamped_on is not old_mesh:
            self._clamped_points = (inside(old_mesh, self.mesh.ngmesh.Coordinates()),
                                    inside(old_mesh, self.mid))
            self._clamped_on = old_mesh
        return self._clamped_points
