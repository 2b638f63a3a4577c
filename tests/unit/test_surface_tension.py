"""The numerical surface tension of section 3.4: turning angles (3.9), curvature (3.10),
its sign, the local profile (3.11) and the trigger."""

import math

import ngsolve as ngs
import numpy as np
import pytest

from granflow.ale.surface_tension import (
    SurfaceTension,
    curvature,
    tension_profile,
    turning_angles,
)
from granflow.geometry.mesh import polygon_mesh


def arc(radius: float, n: int, clockwise: bool = True) -> np.ndarray:
    """n points on the upper half circle, from left to right (clockwise) or back."""
    phi = np.linspace(math.pi * 0.9, math.pi * 0.1, n)
    if not clockwise:
        phi = phi[::-1]
    return radius * np.column_stack([np.cos(phi), np.sin(phi)])


@pytest.mark.parametrize("radius, n", [(0.1, 40), (0.02, 25), (1.0, 200)])
def test_curvature_of_a_circle_is_one_over_the_radius(radius: float, n: int) -> None:
    """The domain under a cap is convex: C = -1/R within 1 % at every interior node."""
    c = curvature(arc(radius, n))
    assert c[0] == 0.0 and c[-1] == 0.0
    assert np.allclose(c[1:-1], -1.0 / radius, rtol=0.01)


def test_sign_convention_convex_negative_concave_positive() -> None:
    """(3.10): negative where the domain (on the right of the chain) is locally convex."""
    bump = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0]])     # a peak of the domain: convex
    dip = np.array([[0.0, 1.0], [1.0, 0.0], [2.0, 1.0]])      # a valley: concave
    assert turning_angles(bump)[0] == pytest.approx(-math.pi / 2)
    assert turning_angles(dip)[0] == pytest.approx(math.pi / 2)
    assert curvature(bump)[1] < 0 < curvature(dip)[1]
    assert curvature(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))[1] == 0.0


def test_turning_angle_of_a_fold_approaches_pi() -> None:
    """A surface that turns back on itself (a fold) turns by almost 180 degrees, and (3.9)
    keeps the sign of the turn up to there."""
    fold = np.array([[0.0, 1.0], [1.0, 1.0], [0.0, 1.01]])
    assert turning_angles(fold)[0] == pytest.approx(math.pi, abs=0.02)


def test_profile_is_one_at_the_critical_node_and_vanishes_beyond_delta() -> None:
    w = tension_profile(60, critical=30, delta=16)
    assert w[30] == 1.0
    assert np.all(w[np.abs(np.arange(60) - 30) >= 16] == 0.0)
    assert np.all(w[np.abs(np.arange(60) - 30) < 16] > 0.0)
    assert np.all(np.diff(w[:31]) >= 0) and np.all(np.diff(w[30:]) <= 0)


def _tension(trigger_deg: float, gamma0: float | str = 2.0,
             release_deg: float | None = None) -> tuple[SurfaceTension, ngs.Mesh]:
    mesh = polygon_mesh([(0, 0), (1, 0), (1, 1), (0, 1)], ["bed", "wall", "surface", "wall"],
                        0.25)
    field = ngs.GridFunction(ngs.H1(mesh, order=1))
    return SurfaceTension(field, delta=2, gamma0=gamma0, trigger_angle_deg=trigger_deg,
                          mesh_size=0.1, release_angle_deg=release_deg), mesh


def _top_chain(mesh: ngs.Mesh) -> np.ndarray:
    xy = mesh.ngmesh.Coordinates()
    top = np.flatnonzero(np.isclose(xy[:, 1], 1.0))
    return top[np.argsort(xy[top, 0])]         # wall to front: the domain on the right


def test_tension_acts_around_the_most_concave_node_once_a_fold_begins() -> None:
    tension, mesh = _tension(trigger_deg=60)
    xy = mesh.ngmesh.Coordinates()
    chain = _top_chain(mesh)
    xy[chain[2], 1] = 0.8                        # a sharp concave notch (turn > 60 deg)
    tension.update([chain], lambda v: 100.0)
    gamma = tension.field.vec.FV().NumPy()
    assert tension.state.active and tension.state.critical_x == pytest.approx(xy[chain[2], 0])
    assert gamma[chain[2]] > 0                      # concave: pushed out
    assert gamma[chain[2]] == pytest.approx(2.0 * curvature(xy[chain])[2])
    assert np.count_nonzero(gamma) <= 3             # delta = 2 nodes: i_c and its neighbours
    tension, _ = _tension(trigger_deg=120)
    tension.update([chain], lambda v: 100.0)
    assert not tension.state.active and not np.any(tension.field.vec.FV().NumPy())


def test_once_on_the_tension_stays_on_until_the_fold_is_below_the_release_angle() -> None:
    """Hysteresis: on at a turn >= 90 deg, off only below 45 deg (no toggling near rest)."""
    tension, mesh = _tension(trigger_deg=90, release_deg=45)
    xy = mesh.ngmesh.Coordinates()
    chain = _top_chain(mesh)
    states = []
    for depth in (0.15, 0.3, 0.15, 0.05, 0.15):   # concave turns 62, 100, 62, 23, 62 deg
        xy[chain[2], 1] = 1.0 - depth
        tension.update([chain], lambda v: 100.0)
        states.append(tension.state.active)
    assert states == [False, True, True, False, False]


def test_a_convex_nose_does_not_trigger_the_tension() -> None:
    """Over a rigid bed the overturning front is a convex nose, landed by deposition."""
    tension, mesh = _tension(trigger_deg=60)
    xy = mesh.ngmesh.Coordinates()
    chain = _top_chain(mesh)
    xy[chain[2], 1] = 1.2                        # a sharp convex peak
    tension.update([chain], lambda v: 100.0)
    assert not tension.state.active


def test_auto_gamma0_is_pressure_under_the_surface_times_mesh_size() -> None:
    tension, mesh = _tension(trigger_deg=0, gamma0="auto")
    xy = mesh.ngmesh.Coordinates()
    chain = _top_chain(mesh)
    xy[chain[2], 1] = 0.99
    tension.update([chain], lambda v: 300.0)
    assert tension.state.gamma0 == pytest.approx(30.0)


def test_auto_gamma0_is_held_while_the_tension_pulls_the_pressure_below_zero() -> None:
    """An acting tension whose own pull leaves no positive pressure under the fold keeps its
    gamma0 (set to 0 it switched off, the pressure came back, it switched on: every other
    step, over a layer stronger than the column); a tension switching on over a pressure
    <= 0 has gamma0 = 0, as before."""
    tension, mesh = _tension(trigger_deg=60, gamma0="auto")
    xy = mesh.ngmesh.Coordinates()
    chain = _top_chain(mesh)
    xy[chain[2], 1] = 0.8
    gammas = []
    for pressure in (300.0, -50.0, 0.0, 200.0):
        tension.update([chain], lambda v, p=pressure: p)
        gammas.append(tension.state.gamma0)
    assert gammas == pytest.approx([30.0, 30.0, 30.0, 20.0])
    assert np.any(tension.field.vec.FV().NumPy())
    fresh, mesh = _tension(trigger_deg=60, gamma0="auto")
    chain = _top_chain(mesh)
    mesh.ngmesh.Coordinates()[chain[2], 1] = 0.8
    fresh.update([chain], lambda v: -50.0)
    assert fresh.state.active and fresh.state.gamma0 == 0.0


def test_local_edge_length_makes_the_traction_the_pressure_times_the_turning_angle() -> None:
    """With length = "local_edge" gamma_i = p w_i delta theta_i (3.8)-(3.11): the edge length
    of (3.10) cancels, so the traction at the fold does not depend on mesh.size, and where
    the edges are mesh.size long it equals the "mesh_size" scaling's."""
    for length in ("mesh_size", "local_edge"):
        for mesh_size in (0.1, 0.4):
            mesh = polygon_mesh([(0, 0), (1, 0), (1, 1), (0, 1)],
                                ["bed", "wall", "surface", "wall"], 0.25)
            field = ngs.GridFunction(ngs.H1(mesh, order=1))
            tension = SurfaceTension(field, delta=2, gamma0="auto", trigger_angle_deg=0,
                                     mesh_size=mesh_size, length=length)
            xy = mesh.ngmesh.Coordinates()
            chain = _top_chain(mesh)
            xy[chain[2], 1] = 0.9
            tension.update([chain], lambda v: 300.0)
            gamma = field.vec.FV().NumPy()[chain]
            turn = turning_angles(xy[chain])[1]            # at node 2, the critical one
            edge = 0.5 * np.sum(np.linalg.norm(np.diff(xy[chain[1:4]], axis=0), axis=1))
            if length == "local_edge":
                assert gamma[2] == pytest.approx(300.0 * turn)
                assert tension.state.gamma0 == pytest.approx(300.0 * edge)
            else:
                assert gamma[2] == pytest.approx(300.0 * mesh_size * turn / edge)
                assert tension.state.gamma0 == pytest.approx(300.0 * mesh_size)


def test_an_unknown_length_is_refused() -> None:
    mesh = polygon_mesh([(0, 0), (1, 0), (1, 1), (0, 1)], ["bed", "wall", "surface", "wall"],
                        0.5)
    with pytest.raises(ValueError, match="surface_tension.length"):
        SurfaceTension(ngs.GridFunction(ngs.H1(mesh, order=1)), delta=2, gamma0="auto",
                       trigger_angle_deg=0, mesh_size=0.1, length="cell")
