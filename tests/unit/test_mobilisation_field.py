"""The mobilisation field on a mesh (fem/mobilisation_field.py): its upwind transport with the
velocity relative to the moving mesh, and its transfer onto a new mesh (ale/transfer.py)."""

import ngsolve as ngs
import numpy as np
from netgen.geom2d import unit_square

from granflow.ale.transfer import transfer_cells
from granflow.fem.mobilisation_field import MobilisationField
from granflow.fem.sampling import triangles


def field_on(maxh: float) -> tuple[MobilisationField, np.ndarray, np.ndarray]:
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=maxh))
    field = MobilisationField(mesh)
    centroids = mesh.ngmesh.Coordinates()[triangles(mesh)].mean(axis=1)
    areas = ngs.Integrate(ngs.CF(1.0), mesh, element_wise=True).NumPy()
    return field, centroids, areas


def test_a_step_is_carried_at_the_flow_speed_and_stays_in_the_unit_interval() -> None:
    """s = 1 left of x = 0.3, carried by u = (1, 0) for 0.4 s on a fixed mesh (h = 0.04,
    steps of 0.02 s, substeps where a cell's in-flux needs them): the front (s = 1/2) and
    the integral of s at 0.3 + 0.4, as in the exact solution (nothing enters through the
    inflow edge x = 0, where s = 1 stays), within 2 h; values in [0, 1]."""
    field, centroids, areas = field_on(0.04)
    field.values[:] = (centroids[:, 0] < 0.3).astype(float)
    still = np.zeros((field.mesh.nv, 2))
    substeps = [field.advect(ngs.CF((1.0, 0.0)), still, 0.02) for _ in range(20)]
    assert max(substeps) >= 2                           # the substeps keep it positive
    assert abs(float(field.values @ areas) - 0.7) < 0.08
    assert field.values.min() >= 0.0 and field.values.max() <= 1.0
    front = centroids[(field.values > 0.45) & (field.values < 0.55), 0]
    assert abs(np.median(front) - 0.7) < 0.08


def test_a_mesh_moving_with_the_flow_carries_the_state_unchanged() -> None:
    """u = w: the state rides on the mesh (exactly); u = 0 with the mesh moving carries it
    backwards relative to the mesh (the material stays where it was)."""
    field, centroids, areas = field_on(0.05)
    field.values[:] = (centroids[:, 0] < 0.5).astype(float)
    before = field.values.copy()
    shift = np.tile([0.01, 0.0], (field.mesh.nv, 1))
    field.advect(ngs.CF((1.0, 0.0)), shift, 0.01)
    assert np.array_equal(field.values, before)
    for _ in range(10):
        field.advect(ngs.CF((0.0, 0.0)), shift, 0.01)
    assert float(field.values @ areas) < float(before @ areas) - 0.05


def test_transfer_keeps_a_constant_and_a_linear_field_to_the_cell_size() -> None:
    old, _, _ = field_on(0.05)
    new, centroids, _ = field_on(0.03)
    old.values[:] = 0.625
    transfer_cells(old.state, new.state)
    assert np.abs(new.values - 0.625).max() < 1e-15
    old.state.Set(ngs.x)
    transfer_cells(old.state, new.state)
    assert np.abs(new.values - centroids[:, 0]).max() < 0.05
    assert np.abs(new.values - centroids[:, 0]).mean() < 0.015
