"""Meshes of three-dimensional domains: a column's section extruded across a channel
(Netgen's OCC kernel), and the periodic box of the plug flow (structured tetrahedra).

Coordinates are (X, Y, Z): X along the slope, Y across the channel, Z normal to the bed,
the bed at Z = 0 and the back wall at X = 0, as the section's (X, Z) in ``geometry/domains.py``.
The channel's centre plane is Y = 0; the side walls are at Y = +-W/2, or, for the half
channel cut along the centre plane, the side wall is at Y = W/2 and the plane Y = 0 is a
symmetry plane (label ``symmetry``).
"""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np
from netgen.meshing import Element2D, Element3D, FaceDescriptor, MeshPoint
from netgen.meshing import Mesh as NgMesh
from netgen.meshing import Pnt as NgPnt
from netgen.occ import Face, OCCException, OCCGeometry, Pnt, Segment, ThruSections, Vec, Wire
from ngsolve.meshes import MakeStructured3DMesh

from granflow.geometry.domains import Polygon
from granflow.geometry.labels import BED, SIDE, SURFACE, SYMMETRY, WALL
from granflow.geometry.mesh import MESHER_FAILURES

# what lofting and meshing a moved body raise when they cannot (``Simulation.mesher_failures``):
# the 2D mesher's types and OCC's own exception (a loft OCC cannot build)
LOFT_FAILURES: tuple[type[Exception], ...] = (*MESHER_FAILURES, OCCException)

# how far (relative to the channel's width) a face's centre may lie off a plane and count on it
_ON_PLANE = 1e-9
ON_PLANE = 1e-9   # m: a vertex this close to a bounding plane is on it


def periodic_box_mesh(length: float, width: float, height: float, size: float) -> ngs.Mesh:
    """Structured tetrahedra of [0, length] x [0, width] x [0, height], periodic in X and Y
    (the 3D layer of configuration (a)); ``bed`` at Z = 0, ``surface`` at Z = height. The
    vertical cell size is exactly height / round(height / size), as the 2D layer's."""
    nz = max(1, round(height / size))
    nx, ny = max(2, round(length / size)), max(2, round(width / size))
    mesh = MakeStructured3DMesh(hexes=False, nx=nx, ny=ny, nz=nz, periodic_x=True,
                                periodic_y=True,
                                mapping=lambda x, y, z: (length * x, width * y, height * z))
    names = mesh.GetBoundaries()
    mesh.ngmesh.SetBCName(names.index("bottom"), BED)
    mesh.ngmesh.SetBCName(names.index("top"), SURFACE)
    return ngs.Mesh(mesh.ngmesh)


@dataclass(frozen=True)
class ChannelSpan:
    """Where a 3D column lies across the channel, Y in [low, high], and the labels of its
    two end faces: the side walls of the whole channel (``side`` both), the half channel
    (``symmetry`` at the centre plane Y = 0, ``side`` at W/2), or a slab between two
    frictionless planes (``symmetry`` both: no side walls, the plane-strain column)."""

    low: float
    high: float
    low_label: str = SIDE
    high_label: str = SIDE

    @classmethod
    def channel(cls, width: float, half: bool = False) -> ChannelSpan:
        if width <= 0:
            raise ValueError(f"boundary.channel_width must be > 0 m, got {width!r}")
        if half:
            return cls(0.0, 0.5 * width, SYMMETRY, SIDE)
        return cls(-0.5 * width, 0.5 * width)

    @classmethod
    def slab(cls, thickness: float) -> ChannelSpan:
        return cls(0.0, thickness, SYMMETRY, SYMMETRY)

    @property
    def width(self) -> float:
        return self.high - self.low

    @property
    def centre(self) -> float:
        """The Y of the channel's centre line (0), or of the slab's first plane."""
        return self.low if self.low_label == self.high_label == SYMMETRY else 0.0

    def held(self, xyz: np.ndarray, tol: float = ON_PLANE) -> np.ndarray:
        """(nv, 3) booleans: the components of each vertex's velocity that must vanish, the
        vertex lying on a bounding plane normal to that axis (the back wall X = 0, a face
        Y = low or high, the bed Z = 0)."""
        return np.column_stack([np.abs(xyz[:, 0]) < tol,
                                (np.abs(xyz[:, 1] - self.low) < tol)
                                | (np.abs(xyz[:, 1] - self.high) < tol),
                                np.abs(xyz[:, 2]) < tol])

    def planes(self) -> tuple[tuple[int, float, str], ...]:
        """(axis, coordinate, label) of the bounding planes."""
        return ((2, 0.0, BED), (0, 0.0, WALL), (1, self.low, self.low_label),
                (1, self.high, self.high_label))


def channel_column_geometry(polygon: Polygon, channel_width: float,
                            half: bool = False) -> OCCGeometry:
    """The section ``polygon`` (X, Z) extruded across the channel: Y in [-W/2, W/2], or
    [0, W/2] when ``half`` (symmetric about the centre plane)."""
    return extruded_geometry(polygon, ChannelSpan.channel(channel_width, half))


def extruded_geometry(polygon: Polygon, span: ChannelSpan) -> OCCGeometry:
    """The section ``polygon`` (X, Z) extruded over Y in the span. Each face extruded from
    an edge keeps the edge's label (``bed``, ``wall``, ``surface``, ...); the end faces
    take the span's labels."""
    pts = [Pnt(x, span.low, z) for x, z in polygon.points]
    n = len(pts)
    section = Face(Wire([Segment(pts[i], pts[(i + 1) % n]) for i in range(n)]))
    solid = section.Extrude(Vec(0.0, span.width, 0.0))
    tol = _ON_PLANE * span.width
    for face in solid.faces:
        c = face.center
        if abs(c.y - span.low) < tol:
            face.name = span.low_label
        elif abs(c.y - span.high) < tol:
            face.name = span.high_label
        else:
            face.name = polygon.labels[_edge_of(polygon, c.x, c.z)]
    return OCCGeometry(solid)


def channel_column_mesh(polygon: Polygon, channel_width: float, size: float,
                        half: bool = False) -> ngs.Mesh:
    """Netgen's tetrahedra of ``channel_column_geometry`` with edges of about ``size``."""
    geometry = channel_column_geometry(polygon, channel_width, half)
    return ngs.Mesh(geometry.GenerateMesh(maxh=size))


def extruded_mesh(polygon: Polygon, span: ChannelSpan, size: float) -> ngs.Mesh:
    """Netgen's tetrahedra of ``extruded_geometry`` with edges of about ``size``."""
    return ngs.Mesh(extruded_geometry(polygon, span).GenerateMesh(maxh=size))


def lofted_mesh(sections: list[np.ndarray], span: ChannelSpan, size: float) -> ngs.Mesh:
    """A body through its sections: ``sections[k]`` is the closed polygon (X, Z) at the
    k-th of ``len(sections)`` equally spaced Y across the span, all with the same number
    of points, starting (0, 0) -> (X_front, 0) along the bed and ending on the back wall;
    Netgen meshes the loft (OCC's ThruSections) with edges of about ``size``. Faces are
    labelled by the plane they lie on (bed, back wall, the span's end faces), the rest is
    free surface: a face lies on a plane when its vertices (the sections' points, exact)
    do. Its bounding box does not say it: OCC pads it by the face's tolerance, which the
    loft can raise past 1e-6 m on an end face."""
    ys = np.linspace(span.low, span.high, len(sections))
    wires = []
    for y, section in zip(ys, sections, strict=True):
        pts = [Pnt(float(x), float(y), float(z)) for x, z in section]
        n = len(pts)
        wires.append(Wire([Segment(pts[i], pts[(i + 1) % n]) for i in range(n)]))
    solid = ThruSections(wires, solid=True)
    for face in solid.faces:
        corners = np.array([[v.p.x, v.p.y, v.p.z] for v in face.vertices])
        face.name = SURFACE
        for axis, value, label in span.planes():
            if np.all(np.abs(corners[:, axis] - value) < ON_PLANE):
                face.name = label
    return ngs.Mesh(OCCGeometry(solid).GenerateMesh(maxh=size))


def _edge_of(polygon: Polygon, x: float, z: float) -> int:
    """The polygon edge nearest to the point (x, z) (a side face's centre lies on it)."""
    pts = polygon.points
    best, index = float("inf"), 0
    for i, (p, q) in enumerate(zip(pts, pts[1:] + pts[:1], strict=True)):
        dx, dz = q[0] - p[0], q[1] - p[1]
        s = ((x - p[0]) * dx + (z - p[1]) * dz) / (dx * dx + dz * dz)
        s = min(1.0, max(0.0, s))
        d = (x - p[0] - s * dx) ** 2 + (z - p[1] - s * dz) ** 2
        if d < best:
            best, index = d, i
    return index


def tetrahedra(mesh: ngs.Mesh) -> np.ndarray:
    """(ne, 4) zero-based vertex indices of the tetrahedra."""
    return mesh.ngmesh.Elements3D().NumPy()["nodes"][:, :4].astype(np.int64) - 1


def signed_volumes(mesh: ngs.Mesh, coords: np.ndarray | None = None) -> np.ndarray:
    """Signed volumes of the tetrahedra (positive = not inverted: Netgen numbers a
    tetrahedron's vertices so that (b - a) x (c - a) . (d - a) < 0)."""
    xyz = mesh.ngmesh.Coordinates() if coords is None else coords
    tet = tetrahedra(mesh)
    a, b, c, d = (xyz[tet[:, k]] for k in range(4))
    return -np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) / 6.0


def tetrahedron_quality(mesh: ngs.Mesh) -> np.ndarray:
    """Shape quality of each tetrahedron, 12 (3 V)^(2/3) / sum of its six squared edge
    lengths: 1 for the regular tetrahedron, 0 for a flat one (negative when inverted)."""
    xyz = mesh.ngmesh.Coordinates()
    tet = tetrahedra(mesh)
    corners = [xyz[tet[:, k]] for k in range(4)]
    edges = sum(np.sum((corners[i] - corners[j]) ** 2, axis=1)
                for i in range(4) for j in range(i + 1, 4))
    volume = signed_volumes(mesh)
    return 12.0 * np.sign(volume) * np.abs(3.0 * volume) ** (2.0 / 3.0) / edges


def boundary_faces(mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """(nf, 3) zero-based vertex indices of the boundary triangles and each one's label."""
    faces = mesh.ngmesh.Elements2D().NumPy()
    names = np.array([mesh.ngmesh.GetBCName(i) for i in range(len(mesh.GetBoundaries()))])
    return faces["nodes"][:, :3].astype(np.int64) - 1, names[faces["index"] - 1]


LABELS_3D = (BED, WALL, SURFACE, SIDE, SYMMETRY)   # a 3D column's faces, in this order


def mesh_arrays(mesh: ngs.Mesh) -> dict[str, np.ndarray]:
    """A 3D column's mesh as plain arrays (a checkpoint's): vertices, tetrahedra, boundary
    triangles and their labels (numbers in ``LABELS_3D``)."""
    faces, labels = boundary_faces(mesh)
    return {"points": mesh.ngmesh.Coordinates().copy(), "tetrahedra": tetrahedra(mesh),
            "faces": faces, "labels": np.array([LABELS_3D.index(str(name))
                                                for name in labels], dtype=np.int64)}


def mesh_from_arrays(points: np.ndarray, tetrahedra: np.ndarray, faces: np.ndarray,
                     labels: np.ndarray) -> ngs.Mesh:
    """The mesh of ``mesh_arrays``, element for element, after checks: indices in range,
    label numbers known, every tetrahedron of positive volume (ValueError otherwise)."""
    n = len(points)
    for name, cells in (("tetrahedra", tetrahedra), ("faces", faces)):
        if cells.size and (cells.min() < 0 or cells.max() >= n):
            raise ValueError(f"the stored mesh's {name} index missing vertices")
    if labels.size and (labels.min() < 0 or labels.max() >= len(LABELS_3D)
                        or len(labels) != len(faces)):
        raise ValueError("the stored mesh's boundary labels are not label numbers")
    new = NgMesh(dim=3)
    marks = [new.Add(MeshPoint(NgPnt(*map(float, p)))) for p in points]
    used = sorted(set(labels.tolist()))
    for k, code in enumerate(used, start=1):
        new.Add(FaceDescriptor(surfnr=k, domin=1, domout=0, bc=k))
        new.SetBCName(k - 1, LABELS_3D[code])
    index = {code: k for k, code in enumerate(used, start=1)}
    for face, code in zip(faces, labels, strict=True):
        new.Add(Element2D(index[int(code)], [marks[int(i)] for i in face]))
    for tet in tetrahedra:
        new.Add(Element3D(1, [marks[int(i)] for i in tet]))
    mesh = ngs.Mesh(new)
    if len(tetrahedra) and signed_volumes(mesh).min() <= 0:
        raise ValueError("the stored mesh has inverted or flat tetrahedra")
    return mesh
