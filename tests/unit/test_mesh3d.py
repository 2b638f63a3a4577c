"""The 3D meshes: a column's section extruded across a channel, with its labelled faces,
and the periodic box of the 3D layer."""

import ngsolve as ngs
import numpy as np
import pytest

from granflow.fem.measure import PLANE, SPACE
from granflow.geometry.domains import column
from granflow.geometry.mesh3d import channel_column_mesh, periodic_box_mesh

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
