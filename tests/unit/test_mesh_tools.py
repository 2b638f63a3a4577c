"""Mesh tools of the moving column: corner triangles, flat slivers, remeshing."""

import numpy as np
import pytest

from granflow.ale.free_surface import BoundaryChain, polygon_area
from granflow.ale.remesh import remesh, shape_quality
from granflow.geometry.domains import column
from granflow.geometry.mesh import (
    BED,
    SURFACE,
    WALL,
    boundary_edge_counts,
    collapse_flat_corners,
    polygon_mesh,
)


def test_initial_column_meshes_have_no_corner_triangles() -> None:
    for shape, size in (("trapezoid", 0.021), ("rectangle", 0.014)):
        poly = column(shape, 0.297 if shape == "trapezoid" else 0.2,
                      0.25 if shape == "trapezoid" else 0.14, 70.0)
        mesh = polygon_mesh(poly.points, poly.labels, size)
        tri = mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(int) - 1
        assert boundary_edge_counts(tri).max() <= 1
        assert polygon_area(mesh.ngmesh.Coordinates(), BoundaryChain(mesh).segments) == (
            pytest.approx(poly.area, rel=1e-12))


def test_flat_corner_sliver_is_collapsed_into_its_chord() -> None:
    xy = np.array([(0, 0), (1, 0), (1, 1), (0.5, 0.9999), (0, 1)], dtype=float)
    tri = np.array([[0, 1, 2], [0, 2, 4], [2, 3, 4]])
    segments = np.array([[0, 1], [1, 2], [2, 3], [3, 4], [4, 0]])
    labels = [BED, SURFACE, SURFACE, SURFACE, WALL]
    xy2, tri2, seg2, lab2 = collapse_flat_corners(xy, tri, segments, labels)
    assert len(xy2) == 4 and len(tri2) == 2 and len(seg2) == 4
    assert lab2 == [BED, SURFACE, SURFACE, WALL]
    assert seg2.tolist() == [[0, 1], [1, 2], [2, 3], [3, 0]]   # the chord replaced 2-3-4
    assert not np.any(np.all(np.isclose(xy2, [0.5, 0.9999]), axis=1))


def test_remesh_keeps_the_labelled_boundary() -> None:
    poly = column("trapezoid", 0.297, 0.25, 70.0)
    mesh = polygon_mesh(poly.points, poly.labels, 0.03)
    xy = mesh.ngmesh.Coordinates()
    xy[:, 0] *= 1.0 + 0.5 * xy[:, 1]          # bend the mesh: a moved domain
    new = remesh(mesh, 0.03)
    old_chain, new_chain = BoundaryChain(mesh), BoundaryChain(new)
    # surface nodes turning the surface by < 2 deg are dropped: the area changes by slivers
    assert polygon_area(new.ngmesh.Coordinates(), new_chain.segments) == pytest.approx(
        polygon_area(xy, old_chain.segments), rel=1e-3)
    for label in (BED, WALL):
        assert set(np.round(new.ngmesh.Coordinates()[new_chain.vertices(label)], 12).ravel()) \
            >= {0.0}
    assert shape_quality(new).min() > 0.2
