"""The ALE move of a 3D column in a channel: the mesh velocity (3.6) or (3.7) in the volume,
the vertices kept on the planes that bound the flow, deposition of the free surface on them,
the volume's drift corrected on the free surface, and a new volume mesh from the moved
surface (the loop's ``MeshMotion``, ``simulation/simulation.py``).

The section's move (``ale/column_mover.py``) walks boundary segments; here the boundary is a
triangulation (Netgen's surface elements of a tetrahedral mesh) and the planes are the bed
Z = 0, the back wall X = 0 and the two faces across the channel (``ChannelSpan``). A vertex
on one of them moves along it: its velocity's normal component is dropped. Section 3.3 in
3D: the step is shortened so that no surface vertex crosses a bounding plane it is not on
(the bed, the back wall, a side wall or the centre plane), the first to reach one landing
on it; a surface triangle lying on a plane takes its label (and its friction and u.N = 0).
Without the landing on the faces across the channel, a surface vertex drifting towards a
side wall at the thinning wall front crossed it, and the step was halved until it came
within 1e-9 m (steps of 1e-8 s). The checks and amounts are volumes (m^3).
"""

from __future__ import annotations

from typing import ClassVar

import ngsolve as ngs
import numpy as np
from netgen.meshing import Element2D, FaceDescriptor, MeshPoint, Pnt
from netgen.meshing import Mesh as NgMesh

from granflow.ale.mesh_motion import AleMover, MeshVelocitySolver, VelocityHistory
from granflow.geometry.labels import SURFACE
from granflow.geometry.mesh3d import (
    LABELS_3D,
    ON_PLANE,
    ChannelSpan,
    boundary_faces,
    signed_volumes,
    tetrahedra,
)
from granflow.simulation.outcomes import MoveFailure
from granflow.state.spec import COUNT, REAL, Share, number

__all__ = ["ChannelMover", "deposit", "remesh_from_surface", "restore_volume",
           "signed_volumes", "surface_volume_gradient", "tetrahedra"]

CROSS = 1e-12           # m: a vertex this far beyond a bounding plane has crossed it
LANDING_TOLERANCE = 1e-9   # relative slack on the landing time of a vertex


class ChannelMover(AleMover):
    """AleMover on tetrahedra: w held on the bounding planes and pure Lagrangian (w = u)
    on the contact lines of the free surface with them, the step limited so that surface
    vertices land on the bed or the back wall, deposition, and the volume correction."""

    share: ClassVar[Share] = {      # its share of a checkpoint (``save_state``)
        "initial_volume": number(0.0, above=True), "relabelled_segments": COUNT,
        "limited_steps": COUNT, "velocity_solves": COUNT, "correction_abs": REAL,
        "correction_net": REAL}

    def __init__(self, mesh: ngs.Mesh, velocity_solver: MeshVelocitySolver,
                 source: ngs.GridFunction, flow: VelocityHistory, target: ngs.GridFunction,
                 span: ChannelSpan, extrapolate: bool = False,
                 conserve_volume: bool = True) -> None:
        super().__init__(mesh, velocity_solver, source, flow, target, extrapolate)
        self.span, self.conserve_volume = span, conserve_volume
        self.initial_volume = self.volume()
        self.relabelled_segments = 0      # surface triangles deposited (the runner's name)
        self.limited_steps = 0
        self.landed: np.ndarray = np.empty((0, 2), dtype=np.int64)   # (vertex, plane)
        self.step_correction = 0.0        # relative volume restored at the last move
        self.correction_abs = 0.0
        self.correction_net = 0.0
        self._surface = np.empty(0, dtype=np.int64)
        self._find_surface()

    def _find_surface(self) -> None:
        faces, labels = boundary_faces(self.mesh)
        self._surface = np.unique(faces[labels == SURFACE])

    # --- checkpoint and remesh ---------------------------------------------------------
    def save_state(self) -> dict[str, object]:
        return {"initial_volume": self.initial_volume,
                "relabelled_segments": self.relabelled_segments,
                "limited_steps": self.limited_steps, "velocity_solves": self.velocity_solves,
                "correction_abs": self.correction_abs, "correction_net": self.correction_net}

    def restore_state(self, state: dict[str, object]) -> None:
        for key in self.share:
            setattr(self, key, state[key])

    def inherit(self, other: ChannelMover) -> None:
        """Carry the reference volume and the counters over a remesh."""
        self.restore_state(other.save_state())

    # --- the step ------------------------------------------------------------------------
    def prepare(self, dt: float) -> float:
        """w for this step, and dt shortened so that no surface vertex crosses a bounding
        plane (the first to reach one lands on it, ``move``)."""
        self._prepare_w(dt)
        assert self.w_vertices is not None
        limited, self.landed = self._landing(dt)
        if limited < dt:
            dt = limited
            self.limited_steps += 1
            if self.extrapolate:          # w for the shortened step; the landed set is kept
                self._prepare_w(dt)
        return dt

    def _prepare_w(self, dt: float) -> None:
        super().prepare(dt)
        assert self.w_vertices is not None
        xyz = self.mesh.ngmesh.Coordinates()
        held = self.span.held(xyz)
        contact = self._surface[held[self._surface].any(axis=1)]
        self.w_vertices[contact] = self.source_at_vertices(dt)[contact]   # section 3.2
        self.w_vertices[held] = 0.0

    def _landing(self, dt: float) -> tuple[float, np.ndarray]:
        """The step to the first landing of a free-surface vertex on a bounding plane it is
        not on, and the landings within it: rows (vertex, plane's index in
        ``span.planes()``)."""
        assert self.w_vertices is not None
        xyz = self.mesh.ngmesh.Coordinates()
        surface = self._surface
        held = self.span.held(xyz)[surface]
        planes = self.span.planes()
        times = np.full((len(surface), len(planes)), np.inf)
        for k, (axis, value, _) in enumerate(planes):
            gap = xyz[surface, axis] - value            # the vertex's side: the inside
            w = self.w_vertices[surface, axis]
            going = ~held[:, axis] & (gap * w < 0)      # moving towards the plane
            times[going, k] = np.maximum(-gap[going] / w[going], 0.0)
        if times.size and float(times.min()) < dt:
            dt = float(times.min())
        landing = np.flatnonzero(times.min(axis=1, initial=np.inf) <= dt * (1 + LANDING_TOLERANCE))
        return dt, np.column_stack([surface[landing], np.argmin(times[landing], axis=1)])

    def move(self, dt: float) -> None:
        super().move(dt)
        xyz = self.mesh.ngmesh.Coordinates()
        planes = self.span.planes()
        for v, k in self.landed:                  # onto the plane it reached first
            axis, value, _ = planes[k]
            xyz[v, axis] = value
        xyz[:, 0] = np.maximum(xyz[:, 0], 0.0)
        xyz[:, 2] = np.maximum(xyz[:, 2], 0.0)
        self.step_correction = 0.0
        if self.conserve_volume:
            self.step_correction = restore_volume(self.mesh, self.initial_volume, self.span)

    def check(self) -> MoveFailure | None:
        if np.any(signed_volumes(self.mesh) <= 0):
            return MoveFailure.INVERTED
        y = self.mesh.ngmesh.Coordinates()[:, 1]
        if y.min() < self.span.low - CROSS or y.max() > self.span.high + CROSS:
            return MoveFailure.CROSSED_WALL
        return None

    def after_accept(self) -> None:
        self.correction_abs += abs(self.step_correction)
        self.correction_net += self.step_correction
        landed = deposit(self.mesh, self.span)
        if landed:
            self.relabelled_segments += landed
            self._find_surface()
        super().after_accept()

    def volume(self) -> float:
        """The body's volume now (m^3)."""
        return float(np.sum(signed_volumes(self.mesh)))


def surface_volume_gradient(mesh: ngs.Mesh) -> np.ndarray:
    """d(volume)/d(vertex position) from the boundary triangles (divergence theorem: V =
    sum over the outward triangles of a . (b x c) / 6); zero at interior vertices."""
    xyz = mesh.ngmesh.Coordinates()
    tri, _ = boundary_faces(mesh)
    a, b, c = (xyz[tri[:, k]] for k in range(3))
    sign = 1.0 if np.einsum("ij,ij->i", a, np.cross(b, c)).sum() > 0 else -1.0  # outward
    grad = np.zeros_like(xyz)
    for k, (p, q) in enumerate(((b, c), (c, a), (a, b))):
        np.add.at(grad, tri[:, k], sign * np.cross(p, q) / 6.0)
    return grad


def restore_volume(mesh: ngs.Mesh, volume: float, span: ChannelSpan,
                   passes: int = 2) -> float:
    """Move the free surface's vertices along the volume's gradient (held on the bounding
    planes) until the body has ``volume`` again: the 3D form of the 2D mover's correction
    of the explicit move's volume drift. Each pass is a Newton step on V(X + lambda g).
    Returns the relative volume restored."""
    tri, labels = boundary_faces(mesh)
    free = np.zeros(mesh.nv, dtype=bool)
    free[np.unique(tri[labels == SURFACE])] = True
    before = float(np.sum(signed_volumes(mesh)))
    for _ in range(passes):
        xyz = mesh.ngmesh.Coordinates()
        grad = surface_volume_gradient(mesh)
        grad[~free] = 0.0
        grad[span.held(xyz)] = 0.0
        norm2 = float(np.sum(grad * grad))
        if norm2 == 0.0:
            break
        xyz += (volume - float(np.sum(signed_volumes(mesh)))) / norm2 * grad
    return (float(np.sum(signed_volumes(mesh))) - before) / volume


def deposit(mesh: ngs.Mesh, span: ChannelSpan, tol: float = ON_PLANE) -> int:
    """Relabel the free-surface triangles whose three vertices lie on one bounding plane
    with that plane's label (section 3.3, Figure 2, in 3D: on the bed they become bed);
    the number relabelled. Forms read the labels when they are assembled."""
    names = [mesh.ngmesh.GetBCName(i) for i in range(len(mesh.GetBoundaries()))]
    surface = [i + 1 for i, name in enumerate(names) if name == SURFACE]
    faces = mesh.ngmesh.Elements2D().NumPy()
    xyz = mesh.ngmesh.Coordinates()
    nodes = faces["nodes"][:, :3].astype(np.int64) - 1
    free = np.isin(faces["index"], surface)
    count = 0
    for axis, value, label in span.planes():
        if label not in names:
            continue
        landed = free & np.all(np.abs(xyz[nodes, axis] - value) < tol, axis=1)
        faces["index"][landed] = names.index(label) + 1
        free &= ~landed
        count += int(np.count_nonzero(landed))
    return count


def remesh_from_surface(mesh: ngs.Mesh, size: float) -> ngs.Mesh:
    """A new tetrahedral mesh of the region bounded by ``mesh``'s boundary triangles (kept
    as they are, with their labels), Netgen's volume mesher filling it with edges of about
    ``size``."""
    tri, labels = boundary_faces(mesh)
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
