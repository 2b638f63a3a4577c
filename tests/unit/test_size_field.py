"""The mesh-size field from the flow (``ale/size_field.py``): fine where the material moves,
coarse where it rests, handed to Netgen as local restrictions; and its plain-data state."""

import numpy as np
import pytest

from granflow.ale.size_field import SizeField, flow_size_field, layer_windows
from granflow.geometry.mesh import polygon_mesh
from granflow.geometry.stretch import LayerStretch

HE = 0.005                      # a 5 mm layer on the bed z = 0
FIELD = SizeField(fine=0.02, coarse=0.04, layer_fine=0.005, layer_coarse=0.02,
                  layer_top=HE, margin=0.06)


def heights(xy: np.ndarray) -> np.ndarray:
    return np.asarray(xy, dtype=float).reshape(-1, 2)[:, 1]


def level(x: np.ndarray) -> np.ndarray:
    return np.zeros_like(np.asarray(x, dtype=float))


def test_windows_are_the_merged_margins_of_the_moving_points_clipped_to_the_layer() -> None:
    points = np.array([[0.30, 0.0], [0.35, 0.0], [0.60, 0.0], [0.05, 0.0]])
    windows = layer_windows(points, 0.06, 0.0, 0.64)
    assert np.allclose(windows, [[0.0, 0.11], [0.24, 0.41], [0.54, 0.64]])
    assert layer_windows(np.zeros((0, 2)), 0.06, 0.0, 1.0).shape == (0, 2)


def test_the_layer_is_fine_only_near_moving_material_close_to_it() -> None:
    """Moving vertices low over the layer make it fine around them; a vertex moving high in
    the column (more than the margin above the layer) does not; resting ones never."""
    xy = np.array([[0.40, 0.006], [0.45, 0.02], [0.10, 0.20], [0.70, 0.004]])
    moving = np.array([True, True, True, False])
    field = flow_size_field(FIELD, xy, moving, heights, end_x=0.8)
    assert np.allclose(field.windows, [[0.34, 0.57]])   # two margins ahead
    assert field.in_windows(np.array([0.35, 0.56])).all()
    assert not field.in_windows(np.array([0.10, 0.70])).any()
    assert field.moving.shape == (3, 2)          # the bulk is fine around all moving ones


def test_uncovered_when_the_flow_comes_within_half_the_margin_of_coarse_cells() -> None:
    layer = SizeField(0.02, 0.02, 0.005, 0.02, HE, 0.06)     # the bulk keeps mesh.size
    field = flow_size_field(layer, np.array([[0.40, 0.0]]), np.array([True]), heights, 0.8)
    assert not field.uncovered(np.array([[0.48, 0.003]]), heights, 0.8)
    assert field.uncovered(np.array([[0.50, 0.003]]), heights, 0.8)   # window ends at 0.52
    assert field.uncovered(np.array([[0.36, 0.003]]), heights, 0.8)   # and starts at 0.34
    far_above = np.array([[0.40, 0.3]])            # the bulk: beyond half the margin
    assert not field.uncovered(far_above, heights, 0.8)
    bulk = flow_size_field(FIELD, np.array([[0.40, 0.0]]), np.array([True]), heights, 0.8)
    assert bulk.uncovered(far_above, heights, 0.8)
    layer_only = flow_size_field(layer, np.array([[0.78, 0.0], [0.01, 0.0]]),
                                 np.array([True, True]), heights, 0.8)
    at_the_ends = np.array([[0.79, 0.003], [0.0, 0.001]])    # the end wall and the wall
    assert not layer_only.uncovered(at_the_ends, heights, 0.8)
    assert not layer_only.uncovered(far_above, heights, 0.8)   # the bulk keeps mesh.size


def test_the_state_is_plain_data_and_gives_the_same_field_back() -> None:
    field = flow_size_field(FIELD, np.array([[0.40, 0.0], [0.2, 0.1]]),
                            np.array([True, True]), heights, 0.8)
    state = field.state()
    assert all(isinstance(v, (np.ndarray, bool)) for v in state.values())
    back = FIELD.from_state(state)
    assert np.array_equal(back.windows, field.windows)
    assert np.array_equal(back.moving, field.moving)
    fresh = SizeField(0.02, 0.02, 0.005, 0.02, HE, 0.06, np.zeros((0, 2)), None)
    assert fresh.from_state(fresh.state()).moving is None


def bed_edges(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Midpoints x and lengths of the mesh's bed edges (z = 0)."""
    xy = mesh.ngmesh.Coordinates()
    seg = mesh.ngmesh.Elements1D().NumPy()["nodes"][:, :2].astype(int) - 1
    on_bed = np.all(np.abs(xy[seg][:, :, 1]) < 1e-12, axis=1)
    p, q = xy[seg[on_bed, 0]], xy[seg[on_bed, 1]]
    return 0.5 * (p[:, 0] + q[:, 0]), np.linalg.norm(q - p, axis=1)


@pytest.mark.parametrize("aspect", [1.0, 2.0])
def test_a_meshed_layer_is_fine_at_the_front_and_coarse_where_it_rests(aspect: float) -> None:
    """A column's foot at x = 0.3 over the layer: the layer's bed edges are at most the
    fine length (in physical x: the meshing length) within the window around the front,
    and several times longer at rest far from it, graded in between."""
    stretch = LayerStretch(HE, aspect)
    fine = aspect * HE / 2
    field = SizeField(0.02, 0.02, fine, 4 * fine, HE, 0.06, np.array([[0.24, 0.40]]), None)
    top = [(x, HE) for x in np.linspace(0.8, 0.3, 26)]     # a free surface's vertices
    points = [(0, 0), (0.8, 0), *top, (0.25, 0.2), (0, 0.2)]
    labels = ["bed", "end", *["surface"] * 27, "wall"]
    sizes = field.edge_size(heights)
    edge_sizes = [sizes(np.array(p), np.array(points[(i + 1) % len(points)]))
                  for i, p in enumerate(points)]
    mesh = polygon_mesh(points, labels, field.maxh, edge_sizes, stretch=stretch,
                        restrict=field.restrictions(level))
    x, length = bed_edges(mesh)
    front = (x > 0.26) & (x < 0.38)
    rest = (x > 0.6) & (x < 0.75)        # (the end wall, 5 mm high, grades the last cells)
    assert length[front].max() <= 1.25 * fine
    assert length[rest].min() >= 2.5 * fine
    assert length[rest].max() <= 4 * fine * 1.25
    uniform = polygon_mesh(points, labels, 0.02, [fine if max(p[1], q[1]) <= 2 * HE else 0.02
                                                  for p, q in zip(points, points[1:] + points[:1],
                                                                  strict=True)],
                           stretch=stretch)
    assert mesh.ne < 0.8 * uniform.ne


def test_overgrown_when_much_of_the_fine_mesh_has_come_to_rest() -> None:
    """The fine layer from 0.1 to 0.6 m: still needed while material moves along it; once
    only the front at 0.55 m moves, the 0.4 m behind it rest and the field must be refit.
    The bulk likewise when most of its fine points are beyond the margin of the flow."""
    field = SizeField(0.02, 0.02, 0.005, 0.02, HE, 0.06, np.array([[0.1, 0.6]]))
    flowing = np.array([[0.2, 0.01], [0.3, 0.01], [0.45, 0.01], [0.55, 0.01]])
    assert not field.overgrown(flowing, heights, 0.8)
    assert field.overgrown(np.array([[0.55, 0.01]]), heights, 0.8)
    fine_points = np.array([[0.2, 0.1], [0.3, 0.1], [0.5, 0.05]])
    bulk = SizeField(0.02, 0.04, margin=0.06, moving=fine_points)
    assert not bulk.overgrown(np.array([[0.25, 0.1], [0.5, 0.06]]), heights, 0.8)
    assert bulk.overgrown(np.array([[0.5, 0.06]]), heights, 0.8)
