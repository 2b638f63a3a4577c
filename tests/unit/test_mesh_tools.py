"""Mesh tools of the moving column: corner triangles, flat slivers, remeshing."""

import numpy as np
import pytest

from granflow.ale.free_surface import BoundaryChain, polygon_area, segments_intersect
from granflow.ale.remesh import kept_boundary_vertices, lengthen_layer, remesh, shape_quality
from granflow.geometry.domains import column
from granflow.geometry.mesh import (
    BED,
    END,
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


def _all_pairs_intersect(xy: np.ndarray, segments: np.ndarray) -> bool:
    """The exact test on every pair of segments (what segments_intersect prunes)."""
    p, q = xy[segments[:, 0]], xy[segments[:, 1]]

    def cross(u: np.ndarray, v: np.ndarray) -> float:
        return float(u[0] * v[1] - u[1] * v[0])

    for a in range(len(segments)):
        for b in range(a + 1, len(segments)):
            if set(segments[a]) & set(segments[b]):
                continue
            d1, d2 = q[a] - p[a], q[b] - p[b]
            r = cross(d1, p[b] - p[a]) * cross(d1, q[b] - p[a])
            s = cross(d2, p[a] - p[b]) * cross(d2, q[a] - p[b])
            if r < 0 and s < 0:
                return True
    return False


def test_pruned_intersection_test_agrees_with_all_pairs() -> None:
    """Random closed polylines with edges of very different lengths, folded and not: the
    k-d tree's candidate pairs lose no crossing."""
    rng = np.random.default_rng(7)
    crossings = 0
    for trial in range(300):
        n = int(rng.integers(4, 40))
        angles = np.sort(rng.uniform(0, 2 * np.pi, n))
        radius = rng.uniform(0.2, 1.0, n) ** (3 if trial % 3 == 0 else 1)
        xy = np.column_stack([radius * np.cos(angles), radius * np.sin(angles)])
        if trial % 2:                                   # swap two vertices: often a fold
            a, b = rng.choice(n, 2, replace=False)
            xy[[a, b]] = xy[[b, a]]
        ring = np.column_stack([np.arange(n), (np.arange(n) + 1) % n])
        expected = _all_pairs_intersect(xy, ring)
        crossings += expected
        assert segments_intersect(xy, ring) == expected
    assert 30 < crossings < 270


def _close_folds_pairwise(points, labels, gap):
    """close_folds as first written: every vertex against every edge in Python loops."""
    from granflow.geometry.mesh import SURFACE

    pts = np.asarray(points, dtype=float)
    n = len(pts)
    for i in [i for i in range(n) if labels[i - 1] == labels[i] == SURFACE]:
        edge = min(np.linalg.norm(pts[i] - pts[i - 1]), np.linalg.norm(pts[(i + 1) % n] - pts[i]))
        for j in range(n):
            if labels[j] != SURFACE or i in (j, (j + 1) % n) or (i - 1) % n == j:
                continue
            a, d = pts[j], pts[(j + 1) % n] - pts[j]
            s = float(np.clip(np.dot(pts[i] - a, d) / max(np.dot(d, d), 1e-300), 0, 1))
            if np.linalg.norm(pts[i] - (a + s * d)) >= gap * edge:
                continue
            forward, backward = (j - i) % n, (i - j - 1) % n
            drop = ({(i + k) % n for k in range(1, forward + 1)} if forward <= backward
                    else {(j + k) % n for k in range(1, backward + 1)})
            if any(labels[k - 1] != SURFACE or labels[k] != SURFACE for k in drop):
                continue
            keep = [k for k in range(n) if k not in drop]
            return _close_folds_pairwise([points[k] for k in keep], [labels[k] for k in keep],
                                         gap)
    return points, labels


def test_vectorised_close_folds_agrees_with_the_pairwise_loops() -> None:
    """Random overturning fronts over a flat layer: the same pockets are cut."""
    from granflow.ale.remesh import FOLD_GAP, close_folds
    from granflow.geometry.mesh import BED, SURFACE, WALL

    rng = np.random.default_rng(3)
    cut = 0
    for _ in range(200):
        m = int(rng.integers(6, 30))
        t = np.linspace(0, 1, m)
        surface = np.column_stack([0.2 + 0.3 * t + rng.normal(0, 0.01, m),
                                   0.2 * (1 - t) ** 2 + rng.uniform(0.0, 0.004, m)])
        points = [(0.0, 0.0), (1.0, 0.0), (1.0, 0.005)] + [tuple(p) for p in surface[::-1]]
        points += [(0.0, 0.2)]
        labels = [BED, BED, SURFACE] + [SURFACE] * m + [WALL]
        expected = _close_folds_pairwise(points, labels, FOLD_GAP)
        assert close_folds(points, labels) == expected
        cut += len(expected[0]) < len(points)
    assert 10 < cut < 190


def test_a_remesh_lengthens_an_erodible_layer_by_its_undisturbed_stretch() -> None:
    """Moving the layer's far end from 0.4 m to 0.6 m adds the 0.2 m x 5 mm stretch: the
    bed runs on, the end rises to the layer's thickness there, the mesh keeps one end edge
    per layer cell, and a layer already longer is left alone."""
    poly = column("trapezoid", 0.297, 0.255, 70.0, erodible_thickness=0.005, bed_length=0.4)
    sizes = [0.0025 if max(p[1], q[1]) <= 0.01 else 0.03
             for p, q in zip(poly.points, poly.points[1:] + poly.points[:1], strict=True)]
    mesh = polygon_mesh(poly.points, poly.labels, 0.03, sizes)
    edge = lambda p, q: 0.0025 if max(p[1], q[1]) <= 0.01 else 0.03  # noqa: E731
    remeshed = remesh(mesh, 0.03, edge, layer_end=0.6, layer_top=0.005)
    assert remeshed.area_added == pytest.approx(0.2 * 0.005, rel=1e-9)
    new_chain = BoundaryChain(remeshed.mesh)
    xy = remeshed.mesh.ngmesh.Coordinates()
    end = new_chain.vertices(END)
    assert len(end) == 3 and np.allclose(xy[end, 0], 0.6)
    assert np.isclose(xy[end, 1].max(), 0.005)
    assert xy[:, 0].max() == pytest.approx(0.6, abs=1e-12)
    assert polygon_area(xy, new_chain.segments) == pytest.approx(poly.area + 0.001, rel=1e-9)
    same = remesh(mesh, 0.03, edge, layer_end=0.3, layer_top=0.005)
    assert same.area_added == 0.0
    assert same.mesh.ngmesh.Coordinates()[:, 0].max() == pytest.approx(0.4, abs=1e-12)
    points, labels = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0)], [BED, SURFACE, WALL]
    with pytest.raises(RuntimeError, match="not one"):
        lengthen_layer(points, labels, 2.0, 0.1)


def test_a_film_lying_back_along_the_bed_is_dropped_before_meshing() -> None:
    """The front's contact point with the surface lying back 1e-12 m above the bed (what a
    hysteretic run with eta = 0.01 Pa s left on a 22 degree bed, where Netgen never
    returned): the tip goes, the bed edge runs to the nearly landed vertex, the loop has
    no angle below SPIKE_RAD and meshes; a loop without spikes is left alone."""
    from granflow.ale.remesh import SPIKE_RAD, drop_spikes

    pts = [(0.0, 0.0), (0.3, 0.0), (0.28, 1e-12), (0.25, 2e-4), (0.2, 0.01), (0.1, 0.03),
           (0.0, 0.04)]
    labels = [BED, SURFACE, SURFACE, SURFACE, SURFACE, SURFACE, WALL]
    new_pts, new_labels = drop_spikes(pts, labels)
    assert new_pts == pts[:1] + pts[2:] and new_labels == [BED, *labels[2:]]
    p = np.array(new_pts)
    a, b = np.roll(p, 1, axis=0) - p, np.roll(p, -1, axis=0) - p
    angles = np.abs(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.sum(a * b, axis=1)))
    assert angles.min() >= SPIKE_RAD
    assert polygon_mesh(new_pts, new_labels, 0.05).ne > 0
    assert drop_spikes(new_pts, new_labels) == (new_pts, new_labels)


# the front of a run (small-eta, 16 degree rigid bed, t = 0.259 s): bed contact, the
# underside of an overturning nose, its tip (index 4), its top, back over the column; the
# top vertex 5 lies on the chord from the underside vertex 2 to the tip (to round-off)
NOSE = [(0.4592266573965774, 0.0), (0.4626025688205759, 0.00061038636831396),
        (0.46491923893815157, 0.0014832012641393718), (0.4681387884236716, 0.0018933843145294241),
        (0.4691708804642059, 0.0037574692454328913), (0.46741024038116064, 0.0028156759773707457),
        (0.4647863955540655, 0.002257167943360953), (0.46159158582594834, 0.0020261869609628047),
        (0.4588164090349876, 0.0028080977034329636), (0.4550500057081034, 0.003869288194560771),
        (0.44, 0.006), (0.40, 0.01), (0.40, 0.0)]


def test_a_flat_triangle_at_a_thin_nose_is_flipped_away(monkeypatch: pytest.MonkeyPatch) -> None:
    """Netgen closes this nose with the triangle (underside, tip, top) of round-off area
    (1.9e-19 m^2), which any move inverts; the flip leaves every triangle at least a
    thousandth of the smallest one Netgen makes elsewhere, and the area is unchanged."""
    from granflow.geometry import mesh as meshes
    from granflow.geometry.mesh import signed_areas

    labels = [SURFACE] * (len(NOSE) - 2) + [WALL, BED]
    fixed = polygon_mesh(NOSE, labels, 0.01)
    monkeypatch.setattr(meshes, "flip_flat_triangles", lambda xy, tri: tri)
    netgen = polygon_mesh(NOSE, labels, 0.01)
    assert signed_areas(netgen).min() < 1e-15          # the case still arises
    assert signed_areas(fixed).min() > 1e-3 * np.sort(signed_areas(netgen))[1]
    assert signed_areas(fixed).sum() == pytest.approx(signed_areas(netgen).sum(), rel=1e-12)
    assert fixed.ne == netgen.ne


def test_flip_flat_triangles_leaves_good_triangles_and_flips_the_long_edge() -> None:
    from granflow.geometry.mesh import flip_flat_triangles

    xy = np.array([[0.0, 0.0], [1.0, -1.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    tri = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [3, 2, 4]])   # (0, 2, 3) is flat
    flipped = flip_flat_triangles(xy, tri)
    assert {tuple(sorted(t)) for t in flipped} == {(0, 1, 3), (1, 2, 3), (0, 3, 4), (2, 3, 4)}
    good = np.array([[0, 1, 2], [0, 2, 4]])
    assert np.array_equal(flip_flat_triangles(xy, good), good)


def test_a_pocket_landed_on_covered_bed_is_seen_and_cut_before_meshing() -> None:
    """A rolling front's air pocket (bed, up over the pocket, down to the bed, bed on) whose
    far end landed behind its near end: two bed edges overlap, collinear, so no edge
    crosses another and Netgen fails on the polygon (what stopped a no-slip run at 22
    degrees with steps of 1e-14 s). The overlap names the pocket's top, whose cut lets the
    polygon mesh with its area kept."""
    from granflow.ale.free_surface import bed_overlaps, crossing_segments, overlap_pocket
    from granflow.geometry.profile import BedProfile

    points = [(0.0, 0.0), (0.6, 0.0), (0.62, 0.01), (0.64, 0.0), (0.7, 0.0), (0.75, 0.05),
              (0.0, 0.1)]
    labels = [BED, SURFACE, SURFACE, BED, SURFACE, SURFACE, WALL]
    mesh = polygon_mesh(points, labels, 0.05)
    xy = mesh.ngmesh.Coordinates()
    chain = BoundaryChain(mesh)
    far_end = int(np.argmin(np.hypot(xy[:, 0] - 0.64, xy[:, 1])))
    top = int(np.argmin(np.hypot(xy[:, 0] - 0.62, xy[:, 1] - 0.01)))
    bed = BedProfile.flat(0.0, 1.0)
    assert not len(bed_overlaps(xy, chain.segments, bed.height, bed.arc_length, 1e-12))
    xy[far_end] = (0.58, 0.0)                       # landed behind the pocket's near end
    assert not len(crossing_segments(xy, chain.segments))
    pairs = bed_overlaps(xy, chain.segments, bed.height, bed.arc_length, 1e-12)
    assert len(pairs)
    cut = overlap_pocket(chain.segments, chain.labels(), chain.index[SURFACE], pairs)
    assert cut.tolist() == [top]
    with pytest.raises(Exception, match="meshing failed"):
        remesh(mesh, 0.05)
    new = remesh(mesh, 0.05, cut=cut).mesh
    assert polygon_area(new.ngmesh.Coordinates(), BoundaryChain(new).segments) == (
        pytest.approx(polygon_area(xy, chain.segments), rel=1e-12))
    assert shape_quality(new).min() > 0.2


def test_the_area_fix_holds_a_vertex_it_would_push_through_the_bed() -> None:
    """A rolling nose's underside 1e-9 m above the bed and an area to restore after a remesh
    lost a sliver: the plain fix pushes the underside under the bed (a move refused at any
    step size); the fix holds those vertices and restores the area with the others. With
    nothing pushed through, it is the plain fix to the last digit."""
    from granflow.ale.free_surface import conserve_above, conserve_area

    xy = np.array([(0.0, 0.0), (0.5, 0.0), (0.6, 1e-9), (0.7, 1e-9), (0.75, 0.004),
                   (0.6, 0.01), (0.3, 0.05), (0.0, 0.1)])
    ring = np.array([[i, (i + 1) % len(xy)] for i in range(len(xy))])
    movable = np.arange(2, 7)
    area = polygon_area(xy, ring)

    def height(p: np.ndarray) -> np.ndarray:
        return p[:, 1] + 1e-12

    plain = xy.copy()
    conserve_area(plain, ring, movable, area * (1 + 4e-6))
    assert height(plain[2:4]).max() < 0                   # pushed through the bed
    held = xy.copy()
    conserve_above(held, ring, movable, area * (1 + 4e-6), height)
    assert np.array_equal(held[2:4], xy[2:4])
    assert polygon_area(held, ring) == pytest.approx(area * (1 + 4e-6), rel=1e-12)
    for target in (area * (1 - 4e-6), area * (1 + 4e-6)):
        shrunk, same = xy.copy(), xy.copy()
        conserve_area(shrunk, ring, movable[2:], target)
        conserve_above(same, ring, movable[2:], target, height)
        assert np.array_equal(shrunk, same)
