"""The ALE move of a 3D column in a channel (prototype): the mesh velocity (3.6) extended
into the volume, the vertices kept on the planes that bound the flow, deposition of the free
surface on the bed, and a new volume mesh from the moved surface.

The section's move (``ale/column_mover.py``) walks boundary segments; here the boundary is a
triangulation (Netgen's surface elements of a tetrahedral mesh) and the planes are the bed
Z = 0, the back wall X = 0, the side wall Y = W/2 (and Y = -W/2, or the symmetry plane Y = 0
of the half channel). A vertex on one of them moves along it: its velocity's normal
component is dropped. The checks and amounts are volumes (m^3).
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from netgen.meshing import Element2D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NgMesh

from granflow.ale.mesh_motion import ElasticMeshVelocity, move_mesh, vertex_values
from granflow.geometry.labels import BED, SIDE, SURFACE, SYMMETRY, WALL
from granflow.geometry.mesh3d import signed_volumes, tetrahedra
from granflow.simulation.outcomes import MoveFailure

ON_PLANE = 1e-9   # m: a vertex this close to a bounding plane is on it
__all__ = ["signed_volumes", "tetrahedra"]


def surface_triangles(mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """(nf, 3) zero-based vertex indices of the boundary triangles and each one's label."""
    faces = mesh.ngmesh.Elements2D().NumPy()
    names = np.array([mesh.ngmesh.GetBCName(i) for i in range(len(mesh.GetBoundaries()))])
    return faces["nodes"][:, :3].astype(np.int64) - 1, names[faces["index"] - 1]


@dataclass(frozen=True)
class ChannelPlanes:
    """The planes that bound a column in a channel of width W (full or half)."""

    channel_width: float
    half: bool = False

    def held(self, xyz: np.ndarray, tol: float = ON_PLANE) -> np.ndarray:
        """(nv, 3) booleans: the components of each vertex's velocity that must vanish (the
        vertex lies on a plane normal to that axis)."""
        y_low = 0.0 if self.half else -0.5 * self.channel_width
        return np.column_stack([np.abs(xyz[:, 0]) < tol,
                                (np.abs(xyz[:, 1] - y_low) < tol)
                                | (np.abs(xyz[:, 1] - 0.5 * self.channel_width) < tol),
                                np.abs(xyz[:, 2]) < tol])


class ChannelMover:
    """dt w on a 3D column: w from (3.6) with the flow's velocity on the boundary, its
    components normal to the bounding planes removed at the vertices on them; the move's
    check (no inverted tetrahedron), its undo, and deposition after it."""

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.GridFunction, planes: ChannelPlanes,
                 penalty: float = 1e8, conserve_volume: bool = False) -> None:
        self.mesh, self.velocity, self.planes = mesh, velocity, planes
        self.target = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
        self._source = ngs.GridFunction(velocity.space)
        self._w = ElasticMeshVelocity(mesh, self._source, self.target, penalty)
        self._saved: np.ndarray | None = None
        self.conserve_volume = conserve_volume
        self.initial_volume = self.volume()

    def vertex_velocity(self) -> np.ndarray:
        """w at the vertices (3.6), held on the bounding planes."""
        self._source.vec.data = self.velocity.vec
        w = vertex_values(self._w.compute())
        w[self.planes.held(self.mesh.ngmesh.Coordinates())] = 0.0
        return w

    def move(self, dt: float) -> MoveFailure | None:
        """Move the vertices by dt w (3.1), land those that cross the bed on it, relabel the
        surface triangles that lie on the bed; undo and report an inverted tetrahedron."""
        w = self.vertex_velocity()
        self._saved = self.mesh.ngmesh.Coordinates().copy()
        move_mesh(self.mesh, dt * w)
        xyz = self.mesh.ngmesh.Coordinates()
        xyz[:, 2] = np.maximum(xyz[:, 2], 0.0)        # deposition: nothing goes below the bed
        if self.conserve_volume:
            restore_volume(self.mesh, self.initial_volume, self.planes)
        if np.any(signed_volumes(self.mesh) <= 0):
            self.undo()
            return MoveFailure.INVERTED
        deposit(self.mesh)
        return None

    def undo(self) -> None:
        if self._saved is not None:
            self.mesh.ngmesh.Coordinates()[:] = self._saved

    def volume(self) -> float:
        return float(np.sum(signed_volumes(self.mesh)))


def surface_volume_gradient(mesh: ngs.Mesh) -> np.ndarray:
    """d(volume)/d(vertex position) from the boundary triangles (divergence theorem: V =
    sum over the outward triangles of a . (b x c) / 6); zero at interior vertices."""
    xyz = mesh.ngmesh.Coordinates()
    tri, _ = surface_triangles(mesh)
    a, b, c = (xyz[tri[:, k]] for k in range(3))
    sign = 1.0 if np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0 else -1.0  # outward
    grad = np.zeros_like(xyz)
    for k, (p, q) in enumerate(((b, c), (c, a), (a, b))):
        np.add.at(grad, tri[:, k], sign * np.cross(p, q) / 6.0)
    return grad


def restore_volume(mesh: ngs.Mesh, volume: float, planes: ChannelPlanes,
                   passes: int = 2) -> None:
    """Move the free surface's vertices along the volume's gradient (held on the bounding
    planes) until the body has ``volume`` again: the 3D form of the 2D mover's correction
    of the explicit move's volume drift. Each pass is a Newton step on V(X + lambda g)."""
    tri, labels = surface_triangles(mesh)
    free = np.zeros(mesh.nv, dtype=bool)
    free[np.unique(tri[labels == SURFACE])] = True
    for _ in range(passes):
        xyz = mesh.ngmesh.Coordinates()
        grad = surface_volume_gradient(mesh)
        grad[~free] = 0.0
        grad[planes.held(xyz)] = 0.0
        norm2 = float(np.sum(grad * grad))
        if norm2 == 0.0:
            return
        xyz += (volume - float(np.sum(signed_volumes(mesh)))) / norm2 * grad


def deposit(mesh: ngs.Mesh, tol: float = ON_PLANE) -> int:
    """Relabel as bed the free-surface triangles whose three vertices lie on the bed
    (section 3.3, Figure 2, in 3D); the number relabelled. A form with only boundary terms
    must then be assembled with ``reallocate=True`` (as in 2D)."""
    names = [mesh.ngmesh.GetBCName(i) for i in range(len(mesh.GetBoundaries()))]
    if BED not in names:
        return 0
    bed = names.index(BED) + 1
    surface = [i + 1 for i, name in enumerate(names) if name == SURFACE]
    faces = mesh.ngmesh.Elements2D().NumPy()
    z = mesh.ngmesh.Coordinates()[:, 2]
    nodes = faces["nodes"][:, :3].astype(np.int64) - 1
    landed = np.isin(faces["index"], surface) & np.all(z[nodes] < tol, axis=1)
    faces["index"][landed] = bed
    return int(np.count_nonzero(landed))


LABELS_3D = (BED, WALL, SURFACE, SIDE, SYMMETRY)


def remesh_from_surface(mesh: ngs.Mesh, size: float) -> ngs.Mesh:
    """A new tetrahedral mesh of the region bounded by ``mesh``'s boundary triangles (kept
    as they are, with their labels), Netgen's volume mesher filling it with edges of about
    ``size``."""
    tri, labels = surface_triangles(mesh)
    used = np.unique(tri)
    renumber = np.full(mesh.nv, -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    new = NgMesh(dim=3)
    points = [new.Add(MeshPoint(Pnt(*map(float, p)))) for p in mesh.ngmesh.Coordinates()[used]]
    names = [name for name in LABELS_3D if name in set(labels)]
    for k, name in enumerate(names, start=1):
        new.Add(FaceDescriptor(surfnr=k, domin=1, domout=0, bc=k))
        new.SetBCName(k - 1, name)
    index = {name: k for k, name in enumerate(names, start=1)}
    for face, label in zip(renumber[tri], labels, strict=True):
        new.Add(Element2D(index[label], [points[int(i)] for i in face]))
    new.GenerateVolumeMesh(maxh=size)
    return ngs.Mesh(new)
