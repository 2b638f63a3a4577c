"""A rolling front folded twice whose surface touches itself: the remesh cuts it into a
simple polygon that Netgen meshes, with the area kept."""

import numpy as np
import pytest
import shapely

from granflow.ale.free_surface import BoundaryChain, crossing_segments, polygon_area
from granflow.ale.remesh import drop_touching, remesh, shape_quality
from granflow.geometry.mesh import BED, SURFACE, WALL, build_mesh

# The front of a glass-bead mu(I) collapse on a no-slip bed at 22 degrees (eta = 0.01 Pa s,
# mesh.size = 0.014 m) at t = 1.17066 s, where its remesh failed (m, to the micrometre;
# behind x = 1.69 m every eighth surface vertex): bed from the wall to the contact point,
# the nose's underside up to its tip, its top back to x = 1.978, forward again under itself
# onto the underside (vertex TOUCHING), back along the sheet to the wall.
NOSE = np.array([
    (0.0, 0.0), (1.990995, 0.0),
    (2.006105, 0.003748), (1.999347, 0.003021), (1.992000, 0.003659), (1.977837, 0.004082),
    (2.000161, 0.002274),
    (1.994767, 0.002152), (1.986472, 0.002048), (1.972536, 0.002235), (1.958951, 0.002370),
    (1.945513, 0.002526), (1.930705, 0.002689), (1.916020, 0.002879), (1.899679, 0.003018),
    (1.883329, 0.003200), (1.866032, 0.003302), (1.848716, 0.003417), (1.836772, 0.003455),
    (1.824806, 0.003513), (1.812878, 0.003581), (1.795325, 0.003612), (1.777709, 0.003685),
    (1.760785, 0.003839), (1.743971, 0.003993), (1.727341, 0.004158), (1.711032, 0.004383),
    (1.694551, 0.004514), (1.677818, 0.004599), (1.538992, 0.005620), (1.414458, 0.007094),
    (1.289854, 0.009042), (1.166155, 0.011778), (1.038016, 0.014606), (0.901127, 0.017499),
    (0.762204, 0.019875), (0.628249, 0.021563), (0.495079, 0.022632), (0.364555, 0.023078),
    (0.234002, 0.022673), (0.101807, 0.021018), (0.0, 0.017436)])
LABELS = [BED] + [SURFACE] * (len(NOSE) - 2) + [WALL]
TOUCHING, UNDERSIDE = 6, 1      # the vertex, and the edge (from vertex 1 to 2) it lies on
OFF = 5e-15                     # m: how far off the underside the run's vertex was
SIZE = 0.014


def touching_nose() -> tuple[np.ndarray, np.ndarray]:
    """The nose with its touching vertex OFF from the underside, on the material's side
    (no edge crosses), and a triangulation of it (constrained Delaunay of the polygon with
    the vertex a micrometre further in: Netgen cannot mesh the touching one)."""
    a, b = NOSE[UNDERSIDE], NOSE[UNDERSIDE + 1]
    along = b - a
    inward = np.array([-along[1], along[0]]) / np.hypot(*along)
    foot = a + np.dot(NOSE[TOUCHING] - a, along) / np.dot(along, along) * along
    pts = NOSE.copy()
    pts[TOUCHING] = foot + 1e-6 * inward
    triangles = shapely.constrained_delaunay_triangles(shapely.Polygon(pts)).geoms
    tri = np.array([[int(np.argmin(np.hypot(*(pts - c).T))) for c in t.exterior.coords[:3]]
                    for t in triangles])
    p = pts[tri]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    clockwise = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
    tri[clockwise] = tri[clockwise][:, ::-1]
    pts[TOUCHING] = foot + OFF * inward
    return pts, tri


def test_a_self_touching_nose_is_cut_into_a_simple_polygon_that_meshes() -> None:
    pts, tri = touching_nose()
    n = len(pts)
    mesh = build_mesh(pts, tri, np.array([[i, (i + 1) % n] for i in range(n)]), LABELS)
    xy, chain = mesh.ngmesh.Coordinates(), BoundaryChain(mesh)
    assert not len(crossing_segments(xy, chain.segments))      # touching, not crossing
    new = remesh(mesh, SIZE).mesh          # before: "folded through itself", RuntimeError
    new_xy, new_chain = new.ngmesh.Coordinates(), BoundaryChain(new)
    assert polygon_area(new_xy, new_chain.segments) == pytest.approx(
        polygon_area(xy, chain.segments), rel=1e-12)
    assert not len(crossing_segments(new_xy, new_chain.segments))
    assert shape_quality(new).min() > 0.1
    assert np.hypot(*(new_xy - pts[TOUCHING]).T).min() > 1e-4   # the touch is gone


def test_dropping_the_touching_vertex_fills_the_fold_between_its_edges() -> None:
    pts, _ = touching_nose()
    points = [tuple(p) for p in pts]
    kept, labels = drop_touching(points, LABELS)
    assert len(kept) == len(points) - 1 and points[TOUCHING] not in kept
    assert labels == LABELS[:TOUCHING] + LABELS[TOUCHING + 1:]
    u, v, w = pts[TOUCHING - 1], pts[TOUCHING], pts[TOUCHING + 1]
    filled = -0.5 * ((v - u)[0] * (w - u)[1] - (v - u)[1] * (w - u)[0])   # air, now material
    assert filled > 0
    ring = np.array([[i, (i + 1) % len(kept)] for i in range(len(kept))])
    whole = np.array([[i, (i + 1) % len(pts)] for i in range(len(pts))])
    assert polygon_area(np.array(kept), ring) - polygon_area(pts, whole) == pytest.approx(
        filled, rel=1e-9)
    away = pts.copy()
    away[TOUCHING, 0] -= 1e-4                     # a tenth of a millimetre off: no touch
    assert drop_touching([tuple(p) for p in away], LABELS)[0] == [tuple(p) for p in away]
