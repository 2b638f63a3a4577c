"""The vectorised point location (fem/locator.py) against NGSolve's own search, on a mesh
whose vertices have moved since it was made (as the ALE moves them)."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
import pytest
from netgen.geom2d import SplineGeometry
from scipy.spatial import cKDTree

from granflow.fem.locator import PointLocator, _barycentric, _lowest, nearest, neighbours
from granflow.fem.sampling import triangles, values_at


def _l_shaped_mesh() -> ngs.Mesh:
    """An L-shaped domain (a concave corner, where a walk can leave the mesh) whose
    vertices are then moved by a smooth map."""
    geo = SplineGeometry()
    points = [(0, 0), (1, 0), (1, 0.4), (0.4, 0.4), (0.4, 1), (0, 1)]
    ids = [geo.AppendPoint(*p) for p in points]
    for a, b in zip(ids, ids[1:] + ids[:1], strict=True):
        geo.Append(["line", a, b])
    mesh = ngs.Mesh(geo.GenerateMesh(maxh=0.08))
    xy = mesh.ngmesh.Coordinates()
    xy += 0.03 * np.column_stack([np.sin(3 * xy[:, 1]), np.sin(2 * xy[:, 0])])
    return mesh


def test_neighbours_are_symmetric_and_share_an_edge() -> None:
    tri = triangles(_l_shaped_mesh())
    across = neighbours(tri)
    for e, row in enumerate(across):
        for k, other in enumerate(row):
            if other < 0:
                continue
            assert e in across[other]
            assert set(tri[e]) - {tri[e][k]} <= set(tri[other])


def test_located_values_agree_with_ngsolve_search() -> None:
    mesh = _l_shaped_mesh()
    space = ngs.VectorH1(mesh, order=2)
    u = ngs.GridFunction(space)
    u.Set(ngs.CF((ngs.sin(4 * ngs.x) * ngs.y, ngs.cos(3 * ngs.y) + ngs.x * ngs.x)))
    xy = mesh.ngmesh.Coordinates()
    rng = np.random.default_rng(3)
    points = np.vstack([
        -0.1 + 1.2 * rng.random((3000, 2)),                  # inside, outside, in the notch
        xy,                                                  # on vertices and the boundary
        xy + 1e-9 * rng.standard_normal(xy.shape),           # within NGSolve's tolerance
        xy + 1e-4 * rng.standard_normal(xy.shape)])
    locator = PointLocator(mesh)
    element, _ = locator.locate(points)
    reference = mesh(np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1]))
    assert np.array_equal(element < 0, reference["nr"] < 0)
    # a point a hair outside the boundary may be read in another triangle within NGSolve's
    # tolerance than NGSolve picks: its field extrapolated 1e-9 m, differently
    assert locator.values(u, points) == pytest.approx(values_at(mesh, u, points), abs=1e-9)
    assert locator.values(u, points[:3000]) == pytest.approx(
        values_at(mesh, u, points[:3000]), abs=1e-14)
    guessed, _ = locator.locate(points, guess=element)      # a warm start finds the same
    assert np.array_equal(guessed < 0, element < 0)


def test_points_on_the_boundary_of_a_concave_mesh_are_inside() -> None:
    """Midpoints of boundary edges, whose walk may stop at another stretch of the boundary,
    are found (a field's value there, not the nearest vertex's)."""
    mesh = _l_shaped_mesh()
    xy = mesh.ngmesh.Coordinates()
    segments = mesh.ngmesh.Elements1D().NumPy()["nodes"][:, :2].astype(np.int64) - 1
    middle = xy[segments].mean(axis=1)
    locator = PointLocator(mesh)
    far = np.full(len(middle), int(np.argmax(xy[triangles(mesh)].mean(axis=1)[:, 0])))
    element, _ = locator.locate(middle, guess=far)           # walks from far away
    assert np.all(element >= 0)
    u = ngs.GridFunction(ngs.H1(mesh, order=2))
    u.Set(ngs.x * ngs.x + ngs.y)
    assert locator.values(u, middle)[:, 0] == pytest.approx(
        middle[:, 0] ** 2 + middle[:, 1], abs=1e-3)


def test_walk_coordinates_are_the_barycentric_ones_bit_for_bit() -> None:
    """The walk's flat per-triangle terms give ``_barycentric``'s numbers exactly, and the
    coordinate it steps across is argmin's (the first of equals; a NaN first)."""
    mesh = _l_shaped_mesh()
    rng = np.random.default_rng(5)
    points = 1.1 * rng.random((2000, 2)) - 0.05
    locator = PointLocator(mesh)
    element, lam = locator.locate(points)
    inside = element >= 0
    corners = mesh.ngmesh.Coordinates()[locator.tri]
    exact = _barycentric(corners[element[inside]], points[inside])
    assert np.array_equal(lam[inside], exact[:, :2])
    a = np.array([0.2, 0.1, 0.1, np.nan, 0.3, 0.0])
    b = np.array([0.1, 0.1, 0.3, 0.2, np.nan, 0.0])
    c = np.array([0.1, 0.3, 0.1, 0.1, 0.1, 0.0])
    lowest, corner = _lowest(a, b, c)
    stacked = np.stack([a, b, c], axis=1)
    assert np.array_equal(corner, np.argmin(stacked, axis=1))
    assert np.array_equal(lowest, stacked.min(axis=1), equal_nan=True)


def test_values_do_not_depend_on_the_order_of_the_points() -> None:
    """Evaluated triangle by triangle, each point's value is the one it has alone."""
    mesh = _l_shaped_mesh()
    u = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
    u.Set(ngs.CF((ngs.sin(4 * ngs.x) * ngs.y, ngs.cos(3 * ngs.y) + ngs.x * ngs.x)))
    points = 0.9 * np.random.default_rng(7).random((500, 2)) + 0.02
    locator = PointLocator(mesh)
    together = locator.values(u, points)
    alone = np.vstack([locator.values(u, p[None]) for p in points[:50]])
    assert np.array_equal(together[:50], alone)


def test_a_few_points_find_the_nearest_site_the_tree_finds() -> None:
    """Without a tree (a few points) the same nearest sites as the k-d tree's."""
    rng = np.random.default_rng(11)
    sites, points = rng.random((900, 2)), 1.2 * rng.random((40, 2)) - 0.1
    assert np.array_equal(nearest(sites, points), cKDTree(sites).query(points)[1])
    many = rng.random((400, 2))
    assert np.array_equal(nearest(sites, many), cKDTree(sites).query(many)[1])
