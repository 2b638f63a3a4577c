"""Mesh tools of the moving column: corner triangles, flat slivers, remeshing."""

import numpy as np
import pytest

from granflow.ale.free_surface import BoundaryChain, polygon_area, segments_intersect
from granflow.ale.remesh import kept_boundary_vertices, remesh, shape_quality
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
    remeshed = remesh(mesh, 0.03)
    new = remeshed.mesh
    old_chain, new_chain = BoundaryChain(mesh), BoundaryChain(new)
    # surface nodes turning the surface by < 2 deg are dropped (slivers of area), and the
    # surface is shifted to restore the area: a remesh conserves it to round-off
    assert 0 < abs(remeshed.area_restored) < 1e-3
    assert polygon_area(new.ngmesh.Coordinates(), new_chain.segments) == pytest.approx(
        polygon_area(xy, old_chain.segments), rel=1e-12)
    for label in (BED, WALL):
        assert set(np.round(new.ngmesh.Coordinates()[new_chain.vertices(label)], 12).ravel()) \
            >= {0.0}
    assert shape_quality(new).min() > 0.2


def test_remesh_merges_a_hairpin_of_overtaking_surface_nodes() -> None:
    """(3.7) lets surface nodes slide; converging ones can overtake and fold the surface
    into a zero-thickness hairpin (seen on the rectangle at half mesh size, t = 0.274 s).
    The remesh merges the bunched nodes so the new boundary is a simple polygon."""
    surface = [(0.40, 0.0), (0.35, 0.020), (0.3039, 0.02006), (0.30387, 0.020066),
               (0.30384, 0.020067), (0.3040, 0.020066), (0.25, 0.03), (0.10, 0.05),
               (0.0, 0.05)]
    pts = np.array([(0.0, 0.0), *surface])
    labels = [BED] + [SURFACE] * (len(surface) - 1) + [WALL]
    keep = kept_boundary_vertices(pts, labels, min_edge=7e-4)
    assert keep == [0, 1, 2, 3, 7, 8, 9]     # the three nodes of the hairpin are merged
    ring = np.array([[i, (i + 1) % len(keep)] for i in range(len(keep))])
    assert not segments_intersect(pts[keep], ring)
    assert pts[6, 0] > pts[3, 0]             # node 6 had overtaken nodes 3 to 5


def test_close_folds_cuts_the_pocket_where_the_front_touches_the_layer() -> None:
    """A nose (vertex 6) come down within a hair of the layer's surface at vertex 3: the
    pocket vertices between them (4, 5) go, the surface runs from the layer to the nose,
    and the wall, bed and end are untouched."""
    from granflow.ale.remesh import close_folds

    pts = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.01), (0.5, 0.01), (0.45, 0.05), (0.5, 0.1),
           (0.49, 0.0101), (0.3, 0.2), (0.0, 0.2)]
    labels = ["bed", "end", "surface", "surface", "surface", "surface", "surface",
              "surface", "wall"]
    new_pts, new_labels = close_folds(pts, labels)
    assert new_pts == [pts[k] for k in (0, 1, 2, 3, 6, 7, 8)]
    assert new_labels == ["bed", "end", "surface", "surface", "surface", "surface", "wall"]
    assert close_folds(pts[:3] + pts[7:], labels[:3] + labels[7:]) == (
        pts[:3] + pts[7:], labels[:3] + labels[7:])     # nothing folded: unchanged
