"""The 3D meshes: a column's section extruded across a channel, with its labelled faces,
and the periodic box of the 3D layer."""

import ngsolve as ngs
import numpy as np
import pytest

from granflow.fem.measure import PLANE, SPACE
from granflow.geometry.domains import column
from granflow.geometry.labels import SURFACE, SYMMETRY, WALL
from granflow.geometry.mesh3d import (
    ChannelSpan,
    channel_column_mesh,
    lofted_mesh,
    periodic_box_mesh,
)

W = 0.1


def face_area(mesh: ngs.Mesh, label: str) -> float:
    return ngs.Integrate(ngs.CF(1.0), mesh, definedon=mesh.Boundaries(label))


@pytest.mark.parametrize("shape", ["rectangle", "trapezoid"])
def test_channel_column_is_the_section_times_the_width(shape: str) -> None:
    polygon = column(shape, 0.2, 0.14, 60.0)
    mesh = channel_column_mesh(polygon, W, 0.04)
    assert ngs.Integrate(ngs.CF(1.0), mesh) == pytest.approx(polygon.area * W, rel=1e-10)
    assert set(mesh.GetBoundaries()) == {"bed", "wall", "surface", "side"}
    assert face_area(mesh, "bed") == pytest.approx(0.2 * W, rel=1e-10)
    assert face_area(mesh, "wall") == pytest.approx(0.14 * W, rel=1e-10)
    assert face_area(mesh, "side") == pytest.approx(2 * polygon.area, rel=1e-10)


def test_half_channel_has_a_symmetry_plane_at_the_centre() -> None:
    polygon = column("rectangle", 0.2, 0.14)
    mesh = channel_column_mesh(polygon, W, 0.04, half=True)
    assert ngs.Integrate(ngs.CF(1.0), mesh) == pytest.approx(polygon.area * W / 2, rel=1e-10)
    assert face_area(mesh, "symmetry") == pytest.approx(polygon.area, rel=1e-10)
    assert face_area(mesh, "side") == pytest.approx(polygon.area, rel=1e-10)
    on_plane = ngs.Integrate(ngs.y * ngs.y, mesh, definedon=mesh.Boundaries("symmetry"))
    assert on_plane == pytest.approx(0.0, abs=1e-20)


def test_channel_width_must_be_positive() -> None:
    with pytest.raises(ValueError, match="boundary.channel_width"):
        channel_column_mesh(column("rectangle", 0.2, 0.14), 0.0, 0.04)


def test_periodic_box_is_periodic_along_and_across() -> None:
    mesh = periodic_box_mesh(0.5, 0.5, 6.0, 0.25)
    assert ngs.Integrate(ngs.CF(1.0), mesh) == pytest.approx(1.5, rel=1e-12)
    assert face_area(mesh, "bed") == pytest.approx(0.25, rel=1e-12)
    space = ngs.Periodic(ngs.H1(mesh, order=1))
    # free vertices of one horizontal layer: 2 x 2 once identified (3 x 3 unperiodic)
    assert sum(space.FreeDofs()) == 4 * (round(6.0 / 0.25) + 1)


def test_3d_coordinates_measure_the_body_in_cubic_metres() -> None:
    """SPACE integrates over the body (m^3), names its amounts as volumes and refuses the
    section's polygon amounts, which would be areas."""
    polygon = column("rectangle", 0.2, 0.14)
    mesh = channel_column_mesh(polygon, W, 0.05)
    assert SPACE.integrate(ngs.CF(1.0), mesh) == pytest.approx(polygon.area * W, rel=1e-12)
    assert (SPACE.amount, SPACE.unit, SPACE.energy_unit) == ("volume", "m3", "J")
    assert (PLANE.amount, PLANE.unit, PLANE.energy_unit) == ("area", "m2", "J/m")
    assert SPACE.integrate(SPACE.bed_normal, mesh) == pytest.approx(
        polygon.area * W * 0.07, rel=1e-12)                # the mean height is h0 / 2
    with pytest.raises(ValueError, match="3D body"):
        SPACE.polygon(np.zeros((3, 2)), np.array([[0, 1], [1, 2], [2, 0]]))


# the two sections (X, Z) of a slab 2 cm thick that a plane-strain run lofted at 0.16 s (to
# 0.1 mm): OCC's loft raises the tolerance of both end faces, so that their bounding boxes
# reach about 1e-5 m off the planes Y = 0 and Y = 0.02
SLAB_SECTIONS = [np.array(points) for points in (
    [[0.0, 0.0], [0.2788, 0.0], [0.2682, 0.0158], [0.2564, 0.0308], [0.245, 0.0463],
     [0.2308, 0.0591], [0.2151, 0.0701], [0.199, 0.0807], [0.1827, 0.0907],
     [0.1658, 0.0999], [0.1484, 0.1081], [0.1308, 0.1156], [0.1129, 0.1225],
     [0.0945, 0.1281], [0.076, 0.1332], [0.0573, 0.1375], [0.0384, 0.1404],
     [0.0192, 0.1408], [0.0, 0.1403]],
    [[0.0, 0.0], [0.2738, 0.0], [0.2682, 0.0156], [0.2561, 0.0305], [0.2449, 0.0461],
     [0.2308, 0.0591], [0.2152, 0.0703], [0.1991, 0.0808], [0.1827, 0.0907],
     [0.1659, 0.0999], [0.1485, 0.1081], [0.1308, 0.1156], [0.1129, 0.1225],
     [0.0946, 0.1282], [0.0761, 0.1332], [0.0573, 0.1373], [0.0384, 0.1403],
     [0.0192, 0.1409], [0.0, 0.1406]])]


def test_a_lofted_body_labels_its_end_faces_whatever_their_tolerance() -> None:
    """Each face of the loft lying on a bounding plane takes its label: the end faces are
    the symmetry planes (each the section's area), the free surface is only the top (its
    area the traces' length times the thickness, within the twist between them)."""
    span = ChannelSpan.slab(0.02)
    mesh = lofted_mesh(SLAB_SECTIONS, span, 0.02)
    areas = {name: ngs.Integrate(ngs.CF(1.0), mesh, definedon=mesh.Boundaries(name))
             for name in set(mesh.GetBoundaries())}
    section = [0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1))
                         - np.dot(p[:, 1], np.roll(p[:, 0], -1))) for p in SLAB_SECTIONS]
    assert areas[SYMMETRY] == pytest.approx(sum(section), rel=1e-9)
    top = [float(np.sum(np.linalg.norm(np.diff(p[1:], axis=0), axis=1)))
           for p in SLAB_SECTIONS]
    assert areas[SURFACE] == pytest.approx(0.02 * np.mean(top), rel=1e-2)
    assert areas[WALL] == pytest.approx(0.02 * np.mean([p[-1, 1] for p in SLAB_SECTIONS]),
                                        rel=1e-9)
