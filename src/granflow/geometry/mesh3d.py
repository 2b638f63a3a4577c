"""Meshes of three-dimensional domains: a column's section extruded across a channel
(Netgen's OCC kernel), and the periodic box of the plug flow (structured tetrahedra).

Coordinates are (X, Y, Z): X along the slope, Y across the channel, Z normal to the bed,
the bed at Z = 0 and the back wall at X = 0, as the section's (X, Z) in ``geometry/domains.py``.
The channel's centre plane is Y = 0; the side walls are at Y = +-W/2, or, for the half
channel cut along the centre plane, the side wall is at Y = W/2 and the plane Y = 0 is a
symmetry plane (label ``symmetry``).
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from netgen.occ import Face, OCCGeometry, Pnt, Segment, Vec, Wire
from ngsolve.meshes import MakeStructured3DMesh

from granflow.geometry.domains import Polygon
from granflow.geometry.labels import BED, SIDE, SURFACE, SYMMETRY

# how far (relative to the channel's width) a face's centre may lie off a plane and count on it
_ON_PLANE = 1e-9


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


def channel_column_geometry(polygon: Polygon, channel_width: float,
                            half: bool = False) -> OCCGeometry:
    """The section ``polygon`` (X, Z) extruded across the channel: Y in [-W/2, W/2], or
    [0, W/2] when ``half`` (symmetric about the centre plane). Each face extruded from an
    edge keeps the edge's label (``bed``, ``wall``, ``surface``, ...); the ends are ``side``
    walls, or ``symmetry`` at Y = 0 for the half channel."""
    if channel_width <= 0:
        raise ValueError(f"boundary.channel_width must be > 0 m, got {channel_width!r}")
    y0 = 0.0 if half else -0.5 * channel_width
    span = 0.5 * channel_width if half else channel_width
    pts = [Pnt(x, y0, z) for x, z in polygon.points]
    n = len(pts)
    section = Face(Wire([Segment(pts[i], pts[(i + 1) % n]) for i in range(n)]))
    solid = section.Extrude(Vec(0.0, span, 0.0))
    tol = _ON_PLANE * channel_width
    for face in solid.faces:
        c = face.center
        if abs(c.y - y0) < tol:
            face.name = SYMMETRY if half else SIDE
        elif abs(c.y - (y0 + span)) < tol:
            face.name = SIDE
        else:
            face.name = polygon.labels[_edge_of(polygon, c.x, c.z)]
    return OCCGeometry(solid)


def channel_column_mesh(polygon: Polygon, channel_width: float, size: float,
                        half: bool = False) -> ngs.Mesh:
    """Netgen's tetrahedra of ``channel_column_geometry`` with edges of about ``size``."""
    geometry = channel_column_geometry(polygon, channel_width, half)
    return ngs.Mesh(geometry.GenerateMesh(maxh=size))


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
