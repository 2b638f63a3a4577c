"""Field transfer across a remesh (ale/transfer.py): values stay those of the old field,
also where the new domain pokes out of the old one, and the velocity is divergence-free."""

import ngsolve as ngs
import numpy as np
import pytest

from granflow.ale.transfer import clamp_all_pairs, clamp_inside, transfer_state, transfer_tensor
from granflow.fem.augmented_lagrangian import tensor_space
from granflow.fem.spaces import taylor_hood
from granflow.geometry.mesh import BED, SURFACE, WALL, polygon_mesh

LABELS = [BED, SURFACE, SURFACE, WALL]


def square(width: float, size: float = 0.2) -> ngs.Mesh:
    return polygon_mesh([(0, 0), (width, 0), (width, 1), (0, 1)], LABELS, size)


def state_on(mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
             pressure: ngs.CoefficientFunction) -> ngs.GridFunction:
    gf = ngs.GridFunction(taylor_hood(mesh))
    gf.components[0].Set(velocity)
    gf.components[1].Set(pressure)
    return gf


def test_points_outside_are_clamped_onto_the_old_boundary() -> None:
    mesh = square(1.0)
    points = np.array([[0.5, 0.5], [1.05, 0.3], [-0.1, 1.2]])
    clamped = clamp_inside(mesh, points)
    assert clamped[0] == pytest.approx([0.5, 0.5])
    assert clamped[1] == pytest.approx([1.0, 0.3], abs=1e-8)
    assert clamped[2] == pytest.approx([0.0, 1.0], abs=1e-8)


def test_a_divergence_free_quadratic_field_is_transferred_exactly() -> None:
    field = ngs.CF((ngs.x * ngs.y, -0.5 * ngs.y * ngs.y))     # P2, div = 0, u.N = 0 on walls
    old = state_on(square(1.0), field, 1000 * (1 - ngs.y))
    new_mesh = square(1.0, size=0.13)                           # same domain, new triangles
    new = ngs.GridFunction(taylor_hood(new_mesh))
    transfer_state(old, new, [BED, WALL], 1e8)
    u, p = new.components
    assert u(new_mesh(0.37, 0.61)) == pytest.approx((0.37 * 0.61, -0.5 * 0.61**2), abs=1e-8)
    assert p(new_mesh(0.3, 0.25)) == pytest.approx(750.0, rel=1e-8)


def test_where_the_new_domain_pokes_out_the_old_field_is_continued() -> None:
    old = state_on(square(1.0), ngs.CF((ngs.x, -ngs.y)), 1000 * (1 - ngs.y))
    new_mesh = square(1.03, size=0.15)                   # pokes 3 cm out of the old domain
    new = ngs.GridFunction(taylor_hood(new_mesh))
    transfer_state(old, new, [BED, WALL], 1e8)
    u = new.components[0]
    # the continued strip is not divergence-free; projecting it perturbs the inside a little
    assert u(new_mesh(0.5, 0.5)) == pytest.approx((0.5, -0.5), abs=1e-3)
    # outside the old domain: the value at the nearest old boundary point, not garbage
    assert u(new_mesh(1.02, 0.5))[0] == pytest.approx(1.0, abs=0.03)


def test_the_projection_removes_the_divergence_of_an_interpolated_field() -> None:
    old = state_on(square(1.0), ngs.CF((ngs.x * ngs.x, 0)), 0 * ngs.x)
    new_mesh = square(1.0, size=0.17)
    new = ngs.GridFunction(taylor_hood(new_mesh))
    transfer_state(old, new, [BED, WALL], 1e8)
    q = ngs.GridFunction(ngs.H1(new_mesh, order=1))
    for k in range(0, new_mesh.nv, 7):                   # discretely divergence-free
        q.vec[:] = 0.0
        q.vec[k] = 1.0
        assert abs(ngs.Integrate(q * ngs.div(new.components[0]), new_mesh)) < 1e-9


def test_a_linear_tensor_field_is_transferred_exactly() -> None:
    """d and lambda of the augmented Lagrangian (discontinuous P1 tensors) keep a field
    linear over the old domain exactly (the vertex values carry it), also where the new
    domain pokes out of the old one."""
    old_mesh, new_mesh = square(1.0), square(1.02, size=0.13)
    field = ngs.CF((ngs.x, ngs.y + 1, ngs.y + 1, 2 * ngs.x - ngs.y), dims=(2, 2))
    old, new = ngs.GridFunction(tensor_space(old_mesh)), ngs.GridFunction(tensor_space(new_mesh))
    old.Set(field)
    transfer_tensor(old, new)
    inside = ngs.IfPos(1.0 - 0.13 - ngs.x, 1.0, 0.0)      # away from the poking-out strip
    error = ngs.Integrate(inside * ngs.InnerProduct(new - field, new - field), new_mesh)
    assert error < 1e-20


def test_clamping_finds_the_same_nearest_boundary_points_as_an_all_pairs_search() -> None:
    """The k-d tree pruning of clamp_inside changes nothing: identical to the digit,
    on a polygon with short and long boundary segments and thousands of outside points."""
    mesh = polygon_mesh([(0, 0), (2.0, 0), (1.5, 0.3), (0.7, 0.45), (0, 0.5)],
                        [BED, SURFACE, SURFACE, SURFACE, WALL], 0.03)
    rng = np.random.default_rng(7)
    points = np.column_stack([rng.uniform(-0.2, 2.2, 3000), rng.uniform(-0.2, 0.7, 3000)])
    clamped = clamp_inside(mesh, points)
    assert np.count_nonzero((clamped != points).any(axis=1)) > 1000   # many were outside
    assert np.array_equal(clamped, clamp_all_pairs(mesh, points))
