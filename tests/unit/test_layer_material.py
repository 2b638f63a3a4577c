"""The tracked layer material (geometry/layer_material.py): exact fractions, area kept by an
area-preserving motion, refinement, coarsening and untangling of the line, erosion depth,
checkpoint round trip."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from granflow.geometry.layer_material import LayerMaterial, coarsened, refined, untangled


def box_mesh(length: float, height: float, nx: int, nz: int) -> tuple[np.ndarray, np.ndarray]:
    """Structured triangles of [0, length] x [0, height]."""
    xs, zs = np.linspace(0, length, nx + 1), np.linspace(0, height, nz + 1)
    gx, gz = np.meshgrid(xs, zs)
    xy = np.column_stack([gx.ravel(), gz.ravel()])
    tri = []
    for j in range(nz):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            tri += [[a, b, c], [a, c, d]]
    return xy, np.array(tri)


def areas(xy: np.ndarray, tri: np.ndarray) -> np.ndarray:
    a, b, c = xy[tri[:, 0]], xy[tri[:, 1]], xy[tri[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def test_fractions_integrate_to_the_region_inside_the_mesh() -> None:
    """A wavy layer top over a box mesh: sum of fraction x area equals the exact area of the
    region inside the box (shapely on the whole), to round-off."""
    layer = LayerMaterial.initial(0.01, 1.0, cells=2)
    layer.line[:, 1] += 0.004 * np.sin(17 * layer.line[:, 0])
    xy, tri = box_mesh(1.0, 0.05, 37, 9)
    f = layer.fractions(xy, tri)
    exact = shapely.intersection(layer.region(), shapely.box(0, 0, 1, 0.05)).area
    assert np.all((f >= 0) & (f <= 1))
    assert (f * areas(xy, tri)).sum() == pytest.approx(exact, rel=1e-12)
    assert 0 < np.count_nonzero((f > 0) & (f < 1)) < len(f) / 2


def test_a_shear_keeps_the_layer_area_and_refines_the_line() -> None:
    """u = (50 (z - h_e), 0) moves every point with a map of determinant 1 and leaves the
    line's ends (at z = h_e) in place: the layer's area stays exact (the area under the
    polyline changes by the telescoping sum (z_end^2 - z_0^2) / 2 = 0 per step); the line is
    refined where the shear stretches it. Coarsening the line where the shear compresses it
    is the only change of area, and it is the one reported (under 1e-6 of the layer)."""
    he = 0.01
    layer = LayerMaterial.initial(he, 1.0, cells=2)
    layer.line[:, 1] += 0.002 * np.sin(2 * np.pi * 6 * layer.line[:, 0])
    box = shapely.box(-10, 0, 10, 1)
    before = shapely.intersection(layer.region(), box).area
    n = len(layer.line)

    def shear(points: np.ndarray) -> np.ndarray:
        return np.column_stack([50 * (points[:, 1] - he), np.zeros(len(points))])

    for _ in range(20):
        layer.advance(shear(layer.line), shear(layer.markers), 0.01)
    after = shapely.intersection(layer.region(), box).area
    assert abs(after - before) <= layer.surgery_area + 1e-15 * before
    assert layer.surgery_area < 1e-6 * before
    assert len(layer.line) > n
    assert np.hypot(*np.diff(layer.line, axis=0).T).max() <= layer.spacing


def test_refined_splits_until_no_segment_is_long() -> None:
    line = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.1]])
    out = refined(line, 0.3)
    assert np.hypot(*np.diff(out, axis=0).T).max() <= 0.3
    assert len(out) == 4 + 1 + 1   # 1 -> 4 pieces, 0.1 stays one


def test_erosion_depth_is_the_deepest_displaced_row() -> None:
    """Markers of the top two of four rows moved 1 cm in the first half of the layer: the
    depth there is half the thickness, zero elsewhere."""
    layer = LayerMaterial.initial(0.008, 1.0, cells=2)
    top_half = (layer.origins[:, 1] > 0.004) & (layer.origins[:, 0] < 0.5)
    velocity = np.where(top_half[:, None], [1.0, 0.0], [0.0, 0.0])
    layer.advance(np.zeros_like(layer.line), velocity, 0.01)
    depth = layer.erosion_depth(0.005, np.linspace(0, 1, 11))
    np.testing.assert_allclose(depth, [0.004] * 5 + [0.0] * 5, atol=1e-15)
    assert layer.displaced(0.005).sum() * layer.marker_area == pytest.approx(0.5 * 0.004)


def test_state_round_trip() -> None:
    layer = LayerMaterial.initial(0.005, 0.5, cells=4)
    layer.advance(np.ones_like(layer.line) * 1e-3, np.ones_like(layer.markers) * 2e-3, 0.1)
    back = LayerMaterial.from_state(layer.save_state())
    for key in ("line", "markers", "origins", "travel"):
        np.testing.assert_array_equal(getattr(back, key), getattr(layer, key))
    assert back.spacing == layer.spacing and back.marker_area == layer.marker_area


def test_bad_layer_is_refused() -> None:
    with pytest.raises(ValueError, match="thickness"):
        LayerMaterial.initial(0.0, 1.0, cells=2)


def curled_line() -> np.ndarray:
    """The top of a 1 cm layer with a curl that crosses itself (right along the top, down,
    back left, up across the top)."""
    line = LayerMaterial.initial(0.01, 1.0, 2).line
    curl = np.array([[0.40, 0.01], [0.46, 0.01], [0.46, 0.005], [0.43, 0.005], [0.43, 0.015],
                     [0.48, 0.015], [0.48, 0.01]])
    return np.vstack([line[line[:, 0] < 0.40], curl, line[line[:, 0] > 0.48]])


def test_a_line_that_crossed_itself_gives_the_union_of_its_loops_and_skips_level_runs() -> None:
    """A material line does not cross itself, but an advected one can, by a numerical error.
    A curl of the line inside the layer (right along the top, down, back left, up across the
    top) turns the same way as the region: the region keeps the curl's inside (the union of
    the loops; repairing by alternating faces would cut a hole there). The level runs of the
    untouched layer are dropped from the polygon, not from the line."""
    material = LayerMaterial.initial(0.01, 1.0, 2)
    material.line = curled_line()
    assert not shapely.LineString(material.line).is_simple
    region = material.region()
    assert region.is_valid
    inside_curl = shapely.box(0.435, 0.006, 0.455, 0.009)
    assert shapely.difference(inside_curl, region).area == pytest.approx(0.0, abs=1e-12)
    layer = shapely.box(0, 0, 1.0, 0.01)
    assert shapely.difference(layer, region).area == pytest.approx(0.0, abs=1e-12)
    assert len(shapely.get_coordinates(region)) < 40         # not one point per 2.5 mm


def test_untangling_keeps_the_outline_of_the_union_of_loops_and_reports_what_it_cut() -> None:
    """The curled line untangled: a simple line from the wall to the layer's end whose region
    is the crossing line's region without the hole the curl encloses, and the area cut is
    that hole's (0.46 - 0.43) x (0.01 - 0.005) ... checked against the two regions."""
    line = curled_line()
    repaired = LayerMaterial(line, np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0),
                             0.0025, 0.01, 1.0).region()
    new, cut = untangled(line)
    assert shapely.LineString(new).is_simple
    np.testing.assert_array_equal(new[0], line[0])
    np.testing.assert_array_equal(new[-1], line[-1])
    after = LayerMaterial(new, np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0),
                          0.0025, 0.01, 1.0).region()
    assert after.is_valid and shapely.difference(after, repaired).area < 1e-12
    assert cut == pytest.approx(shapely.difference(repaired, after).area, rel=1e-9)
    assert cut < 0.03 * 0.01                 # at most the curl's box
    assert untangled(new)[1] == 0.0          # a simple line: nothing cut


def test_coarsening_merges_short_flat_segments_and_counts_the_area_it_moves() -> None:
    """A convex arc sampled 20 times finer than the spacing: coarsened to segments no longer
    than the spacing, the corners it removed adding up to the area between the two lines
    (all on one side of the arc, so the sum is exact); a straight line loses nothing."""
    spacing = 0.001
    x = np.linspace(0.0, 0.1, 2001)
    arc = np.column_stack([x, 0.01 + 0.05 * x * (0.1 - x)])
    new, changed = coarsened(arc, spacing)
    segments = np.hypot(*np.diff(new, axis=0).T)
    assert len(new) < len(arc) / 10 and segments.max() <= spacing
    between = shapely.Polygon(np.vstack([arc, new[::-1]])).area
    assert changed == pytest.approx(between, rel=1e-6) and changed > 0
    straight = np.column_stack([x, np.full_like(x, 0.01)])
    flat, moved = coarsened(straight, spacing)
    assert moved == 0.0 and len(flat) < len(straight) / 10


def test_a_folding_flow_leaves_a_simple_short_line() -> None:
    """A velocity whose explicit step is not one-to-one (it moves points past each other,
    as at a churning front): refinement alone leaves a line of thousands of points that
    crosses itself; kept at its resolution, the line stays simple, with under a tenth of
    the points, and the correction (the loops cut off) is reported and small."""
    k, dt = 2 * np.pi / 0.02, 0.01

    def folding(line: np.ndarray, step: int) -> np.ndarray:
        x = line[:, 0]
        bump = np.exp(-(((x - 0.1) / 0.03) ** 2))
        return np.column_stack([3.0 / (k * dt) * np.sin(k * x + step) * bump,
                                0.2 * np.cos(k * x + step) * bump])

    kept = LayerMaterial.initial(0.005, 0.2, cells=1)
    raw = kept.line.copy()
    for step in range(30):
        raw = refined(raw + dt * folding(raw, step), kept.spacing)
        kept.advance(folding(kept.line, step), np.zeros_like(kept.markers), dt)
    assert not shapely.LineString(raw).is_simple and len(raw) > 4000
    assert shapely.LineString(kept.line).is_simple and len(kept.line) < 0.1 * len(raw)
    assert 0 < kept.surgery_area < 0.01 * kept.initial_area
