"""Collapses on a user's geometry against the paper's set-ups: a built-in column written as a
polygon on a level profile is the same run; a profile of one segment at 10 degrees is the
run with gravity turned by 10 degrees (``geometry.slope_deg``), turned; a front that crosses
a slope change leaves a mesh vertex on the corner and every node on or above the bed."""

import math

import numpy as np
import pytest

from granflow.ale.free_surface import BoundaryChain
from granflow.config import load_config
from granflow.geometry.labels import BED
from granflow.scenarios.column import build_column

COARSE = ["mesh.size=0.05", "time.output_times=[]"]
TOP = 0.297 - 0.25 / math.tan(math.radians(70.0))


def _run(overrides: list[str]):  # type: ignore[no-untyped-def]
    problem = build_column(load_config("trapezoid-rigid", [*COARSE, *overrides]))
    result = problem.simulation.run()
    return problem, result


def test_the_trapezoid_as_a_polygon_on_a_level_profile_is_the_same_run() -> None:
    """Same steps, iterations and nodes to the last digit (0.2 s: a surface edge has landed
    on the bed and the mesh has been remeshed once)."""
    mass = f"[[0.0, 0.0], [0.297, 0.0], [{TOP!r}, 0.25], [0.0, 0.25], [0.0, 0.0]]"
    a, ra = _run(["time.t_end=0.2"])
    b, rb = _run(["time.t_end=0.2", f"geometry.mass={mass}",
                  "geometry.bed_profile=[[0.0, 0.0], [1.5, 0.0]]"])
    assert (ra.steps, ra.nonlinear_iterations) == (rb.steps, rb.nonlinear_iterations)
    assert np.array_equal(a.mesh.ngmesh.Coordinates(), b.mesh.ngmesh.Coordinates())
    assert a.mover.relabelled_segments == b.mover.relabelled_segments == 1
    assert a.remesher.remeshes == b.remesher.remeshes == 1


def test_a_ten_degree_profile_is_the_slope_run_turned() -> None:
    """The trapezoid on a profile descending at 10 degrees (gravity vertical) against the
    trapezoid on the level bed with gravity turned by 10 degrees: the same mesh turned, the
    same steps and iterations, the nodes within 1e-8 m of the turned ones after 0.05 s
    (the solves converge to 3e-5; the difference is the turning's round-off carried
    through them) and the kinetic energy within 1e-7."""
    theta = math.radians(10)
    t = np.array([math.cos(theta), -math.sin(theta)])
    n = np.array([math.sin(theta), math.cos(theta)])
    slope, rs = _run(["time.t_end=0.05", "geometry.slope_deg=10"])
    end = [2 * float(t[0]), 2 * float(t[1])]
    profile, rp = _run(["time.t_end=0.05",
                        f"geometry.bed_profile=[[0.0, 0.0], [{end[0]!r}, {end[1]!r}]]"])
    assert (rs.steps, rs.nonlinear_iterations) == (rp.steps, rp.nonlinear_iterations)
    xy = profile.mesh.ngmesh.Coordinates()
    turned = np.column_stack([xy @ t, xy @ n])
    assert turned == pytest.approx(slope.mesh.ngmesh.Coordinates(), abs=1e-8)
    assert profile.solver.kinetic_energy() == pytest.approx(slope.solver.kinetic_energy(),
                                                            rel=1e-7)
    assert slope.solver.kinetic_energy() > 1e-2        # it moves


def test_a_front_crossing_a_slope_change_keeps_the_corner() -> None:
    """A rectangle released on a 16-degree plane that turns level 10 cm ahead of it: once
    the front is on the level floor a mesh vertex sits on the corner (no bed edge spans
    it), every node is on or above the bed, the volume is conserved."""
    theta = math.radians(16)
    corner = [0.3 * math.cos(theta), -0.3 * math.sin(theta)]
    problem = build_column(load_config("incline-to-floor", [
        "mesh.size=0.04", "time.t_end=0.25", "time.output_times=[]",
        f"geometry.bed_profile=[[0.0, 0.0], [{corner[0]!r}, {corner[1]!r}], "
        f"[1.5, {corner[1]!r}]]"]))
    area0 = problem.mover.area()
    result = problem.simulation.run()
    assert result.status == "completed", result.message
    xy = problem.mesh.ngmesh.Coordinates()
    assert xy[:, 0].max() > corner[0] + 0.05            # the front is on the floor
    bed = problem.mover.support.bed
    assert bed.height(xy).min() > -1e-12
    chain = BoundaryChain(problem.mesh)
    assert np.hypot(*(xy[chain.vertices(BED)] - np.array(corner)).T).min() < 1e-12
    assert not problem.mover.straddles_corner()
    assert problem.mover.area() == pytest.approx(area0, rel=1e-12)
