"""Cells stretched along an erodible layer (``geometry/stretch.py``): the map, the first mesh,
and a remesh that lengthens the layer keep the cells' shape and the domain's area."""

import numpy as np
import pytest

from granflow.ale.free_surface import BoundaryChain, polygon_area
from granflow.ale.remesh import remesh, shape_quality
from granflow.config import load_config
from granflow.fem.sampling import triangles
from granflow.geometry.domains import column
from granflow.geometry.mesh import END
from granflow.geometry.stretch import LayerStretch
from granflow.scenarios.column import build_column
from granflow.scenarios.column_setup import ColumnSetup

HE = 0.005


def test_the_map_and_its_inverse() -> None:
    """z' = a z in the layer, z + (a - 1) h_e above: continuous at h_e, inverted exactly."""
    stretch = LayerStretch(HE, 4.0)
    xy = np.array([[0.1, 0.0], [0.2, 0.002], [0.3, HE], [0.4, 0.1]])
    mapped = stretch.forward(xy)
    assert mapped[:, 1] == pytest.approx([0.0, 0.008, 4 * HE, 0.1 + 3 * HE], rel=1e-14)
    assert np.array_equal(mapped[:, 0], xy[:, 0])
    assert stretch.inverse(mapped) == pytest.approx(xy, rel=1e-14, abs=1e-17)
    assert LayerStretch(HE, 1.0).identity and LayerStretch(0.0, 4.0).identity


def _layer_cells(mesh, top: float) -> tuple[np.ndarray, np.ndarray]:
    """Lengths along x and across z of the triangles wholly inside the layer."""
    p = mesh.ngmesh.Coordinates()[triangles(mesh)]
    inside = p[:, :, 1].max(axis=1) <= top + 1e-12
    span = p[inside].max(axis=1) - p[inside].min(axis=1)
    return span[:, 0], span[:, 1]


@pytest.mark.parametrize("aspect", [4.0, 8.0])
def test_the_layers_cells_are_stretched_by_the_aspect(aspect: float) -> None:
    """Two cells across a 5 mm layer (2.5 mm high) come out about aspect x 2.5 mm long; the
    mesh has far fewer triangles than the isotropic one, all of good quality in the
    coordinates it was made in (the uniform mesh: the adaptive one also coarsens the layer
    at rest)."""
    iso = build_column(load_config("trapezoid-erodible", ["mesh.layer_cells=2",
                                                          "mesh.layer_aspect=1",
                                                          "mesh.adaptive=false"]))
    config = load_config("trapezoid-erodible", ["mesh.layer_cells=2", "mesh.adaptive=false",
                                                f"mesh.layer_aspect={aspect}"])
    stretched = build_column(config)
    along, across = _layer_cells(stretched.mesh, HE)
    assert np.median(across) == pytest.approx(HE / 2, rel=0.05)
    assert np.median(along) == pytest.approx(aspect * HE / 2, rel=0.25)
    assert stretched.mesh.ne < 0.45 * iso.mesh.ne
    assert shape_quality(stretched.mesh, ColumnSetup.of(config).stretch).min() > 0.4


def test_a_remesh_and_a_lengthening_keep_the_stretched_cells_and_the_area() -> None:
    """A bent stretched mesh remeshed with its layer lengthened from 0.4 to 0.6 m: the area
    grows by the added stretch only (about 0.2 m x h_e), the layer keeps two cells across
    (its end: two edges) and its aspect, and the quality stays bounded."""
    config = load_config("trapezoid-erodible", ["mesh.layer_cells=2", "mesh.layer_aspect=4",
                                                "mesh.size=0.03", "geometry.bed_length=0.4"])
    stretch = ColumnSetup.of(config).stretch
    poly = column("trapezoid", 0.297, 0.255, 70.0, erodible_thickness=HE, bed_length=0.4)
    problem = build_column(config)
    mesh = problem.mesh
    xy = mesh.ngmesh.Coordinates()
    area0 = polygon_area(xy, BoundaryChain(mesh).segments)
    assert area0 == pytest.approx(poly.area, rel=1e-12)
    xy[:, 0] += 0.02 * np.sin(np.pi * xy[:, 1] / 0.255) * (xy[:, 1] > HE)   # moved
    area1 = polygon_area(xy, BoundaryChain(mesh).segments)
    remeshed = remesh(mesh, 0.03, ColumnSetup.of(config).layer_edge_sizes(), layer_end=0.6,
                      layer_top=HE, stretch=stretch)
    new = remeshed.mesh
    chain = BoundaryChain(new)
    # (the surface was shifted by micrometres to restore the area the remesh's simplified
    # surface lost, so the layer's old end is not exactly h_e high)
    assert remeshed.area_added == pytest.approx(0.2 * HE, rel=1e-2)
    assert polygon_area(new.ngmesh.Coordinates(), chain.segments) == pytest.approx(
        area1 + remeshed.area_added, rel=1e-9)
    assert np.sum(chain.labels() == chain.index[END]) == 2
    along, across = _layer_cells(new, HE)
    assert np.median(along / across) == pytest.approx(4.0, rel=0.3)
    assert shape_quality(new, stretch).min() > 0.3


def test_an_edge_crossing_the_layers_top_is_split_there() -> None:
    """The map is linear on each side only: an edge from below the layer's top to above it
    gets a vertex on the top, so that it stays straight and the area is kept."""
    stretch = LayerStretch(HE, 4.0)
    square = np.array([[0.0, 0.0], [0.1, 0.0], [0.1, 0.02], [0.0, 0.001]])
    split, edge = stretch.split(square)
    assert edge.tolist() == [0, 1, 1, 2, 2, 3]          # the right side and the top cross
    assert split[2] == pytest.approx([0.1, HE]) and split[4][1] == pytest.approx(HE)
    mesh_area = polygon_area(stretch.inverse(stretch.forward(split)),
                             np.array([[i, (i + 1) % 6] for i in range(6)]))
    assert mesh_area == pytest.approx(polygon_area(square, np.array(
        [[i, (i + 1) % 4] for i in range(4)])), rel=1e-12)
    # a crossing 1 % from an end of its edge is left (a sliver Netgen cannot mesh)
    nearly = np.array([[0.0, 0.0], [0.1, 0.0], [0.1, 1.01 * HE], [0.0, 1.01 * HE]])
    assert len(stretch.split(nearly)[0]) == 4
