"""The hysteretic friction (physics/hysteresis.py) in the 2D solver.

The incline: a periodic Drucker-Prager layer, 1 cm deep (8 cells across), flow angle 20 deg,
start angle 25 deg, viscosity 0.3 Pa s (steady within 1e-3 after ~1.5 s). Between the two
angles (22.5 deg) it holds when released at rest and keeps flowing, towards the parabola of
its flow friction (reference/incline.py), when released in motion: the h_stop / h_start
hysteresis. Above the start angle (27 deg) it flows from rest to the same parabola.

The column: the state on the moving mesh through a remesh, a layer's lengthening and a
checkpoint, the per-point friction of the primal-dual correction, and the outputs.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import granflow
from granflow.config import load_config
from granflow.physics.hysteresis import Hysteretic
from granflow.scenarios.column import ColumnCollapse, build_column
from granflow.scenarios.plug_flow import PlugFlow, build_plug_flow

INCLINE = ["mesh.size=0.00125", "time.dt=5e-3", "time.t_end=1.5", "time.output_times=[]",
           "material.rheology=drucker-prager", "material.viscosity=0.3",
           "material.friction_angle_deg=20", "material.friction=hysteretic",
           "material.start_friction_angle_deg=25", "numerics.tol=1e-6",
           "numerics.linearization=primal-dual"]
IN_MOTION = ["material.initial_mobilisation=1", "initial.shear_rate=10",
             "initial.plug_base=0"]          # u = 10 z: every cell sheared above 1 1/s

Twins = Callable[..., tuple[ColumnCollapse, ...]]   # conftest.py: checkpoint_twins


def incline(*overrides: str) -> PlugFlow:
    problem = build_plug_flow(load_config("incline-mu-i", [*INCLINE, *overrides]))
    result = problem.simulation.run()
    assert result.status == "completed", result.message
    return problem


def top_speed(problem: PlugFlow) -> float:
    _, u, _ = problem.profile(problem.simulation.t)
    return float(np.abs(u).max())


def test_a_layer_between_the_stop_and_start_angles_released_at_rest_holds() -> None:
    """At rest (s = 0) the start friction holds it: only the regularisation's creep (the
    stress ratio tan 22.5 / tan 25 = 0.89 gives |Du| ~ 2 eps, 3e-8 m/s at the top), and the
    state stays at rest."""
    problem = incline("geometry.slope_deg=22.5")
    assert problem.mobilisation is not None
    assert top_speed(problem) < 1e-6
    assert problem.mobilisation.values.max() == 0.0


def test_the_same_layer_released_in_motion_keeps_flowing_to_the_flow_profile() -> None:
    """Mobilised (s = 1) and sheared, it flows on to the parabola of mu_flow = tan 20 deg
    (0.114 m/s at the top) within 1 % (relative L2); only the top row of cells, where the
    parabola's shear rate falls below the threshold, rides on it as a plug at rest."""
    problem = incline("geometry.slope_deg=22.5", *IN_MOTION)
    assert problem.reference_kind == "steady"
    error = problem.velocity_error(problem.simulation.t)
    assert error < 0.01, error
    assert problem.mobilisation is not None
    assert np.mean(problem.mobilisation.values) > 0.8


def test_a_layer_above_the_start_angle_flows_from_rest() -> None:
    """At 27 deg the start friction does not hold it: it mobilises (s -> 1 everywhere) and
    reaches the parabola of mu_flow (0.318 m/s at the top) within 1 %."""
    problem = incline("geometry.slope_deg=27")
    error = problem.velocity_error(problem.simulation.t)
    assert error < 0.01, error
    assert problem.mobilisation is not None
    assert problem.mobilisation.values.min() > 0.99


COLUMN = ["mesh.size=0.04", "time.output_times=[]", "time.stop_at_rest=false",
          "material.friction=hysteretic"]


def column(*overrides: str, scenario: str = "rectangle-rigid") -> ColumnCollapse:
    return build_column(load_config(scenario, [*COLUMN, *overrides]))


def test_the_state_crosses_a_remesh_and_is_advanced_once_per_step() -> None:
    """After 0.1 s of collapse (part of the column mobilised), a forced remesh carries s onto
    the new mesh: the mobilised fraction within 3 %, values in [0, 1]; the state's time is
    the loop's after every step."""
    problem = column("time.t_end=0.1")
    problem.simulation.run()
    tracking = problem.mobilisation
    assert tracking is not None and tracking.t == problem.simulation.t
    before = tracking.mobilised_fraction()
    assert 0.1 < before < 0.9
    mesh = problem.mesh
    problem.remesher.remesh()
    assert problem.mesh is not mesh and problem.remesher.remeshes >= 1
    after = tracking.mobilised_fraction()
    assert abs(after / before - 1) < 0.03, (before, after)
    values = tracking.field.values
    assert values.min() >= 0.0 and values.max() <= 1.0


def test_a_lengthened_layer_gets_the_state_of_material_at_rest_since_the_start() -> None:
    """A layer mobilised at t = 0 (layer.initial_mobilisation = 1) relaxes where it stays at
    rest: the stretch a remesh adds ahead of the flow at t = 0.05 s gets exp(-t / tau_r)."""
    problem = column("geometry.erodible_thickness=0.01", "mesh.layer_cells=1",
                     "geometry.bed_length=0.5", "mesh.layer_ahead=0.06",
                     "layer.friction=hysteretic", "material.friction=constant",
                     "layer.initial_mobilisation=1", "layer.rest_time=0.04",
                     scenario="trapezoid-erodible")
    tracking = problem.mobilisation
    assert tracking is not None
    old_end = problem.mover.end_x
    problem.simulation.t = tracking.t = 0.05
    problem.remesher.layer_end_due = lambda: old_end + 0.1        # type: ignore[method-assign]
    problem.remesher.remesh()
    assert problem.mover.end_x == pytest.approx(old_end + 0.1)
    xy = problem.mesh.ngmesh.Coordinates()
    corners = xy[problem.mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(int) - 1]
    added = corners.mean(axis=1)[:, 0] > old_end
    assert added.sum() > 0
    np.testing.assert_allclose(tracking.field.values[added], math.exp(-0.05 / 0.04), rtol=1e-14)


def test_a_checkpoint_restores_the_state_and_the_run_goes_on_as_before(
        tmp_path: Path, checkpoint_twins: Twins) -> None:
    """Through the checkpoint file (data only): s and its time come back exactly, and the
    restored run ends where the uninterrupted one does: s within 1e-3, u within 1e-3 of
    its largest value (a restored run with a constant friction differs from its
    uninterrupted twin by 2e-4: the nonlinear iteration's own history is not saved)."""
    straight, first, twin = checkpoint_twins(column, tmp_path)
    assert first.mobilisation is not None and twin.mobilisation is not None
    np.testing.assert_array_equal(twin.mobilisation.field.values,
                                  first.mobilisation.field.values)
    assert twin.mobilisation.t == first.mobilisation.t
    twin.simulation.run()
    assert straight.mobilisation is not None
    np.testing.assert_allclose(twin.mobilisation.field.values,
                               straight.mobilisation.field.values, rtol=0, atol=1e-3)
    u, v = (p.solver.previous.vec.FV().NumPy() for p in (twin, straight))
    assert np.abs(u - v).max() <= 1e-3 * np.abs(v).max()
    assert np.abs(twin.mobilisation.field.values - first.mobilisation.field.values).max() > 0.01


def test_primal_dual_reads_the_friction_of_each_point() -> None:
    """The correction's yield slope is sqrt(2) ((1 - s) mu_start + s mu_flow) at each
    quadrature point (three per triangle, from the triangle's s)."""
    problem = column("time.t_end=0.05")
    problem.simulation.run()
    dual = problem.solver.nonlinear.dual
    law = problem.solver.rheology
    assert dual is not None and isinstance(law, Hysteretic)
    s = np.repeat(problem.mobilisation.field.values, 3)        # type: ignore[union-attr]
    mu = (1 - s) * math.tan(math.radians(27.5)) + s * math.tan(math.radians(25.5))
    assert s.min() < 0.5 < s.max()
    np.testing.assert_allclose(dual._yield_slope(), math.sqrt(2) * mu, rtol=1e-14)


def test_the_outputs_carry_the_state(tmp_path: Path) -> None:
    """fields/ has the cell field ``mobilisation``, diagnostics.csv ``mobilised_fraction``
    (0 at rest, rising as the column collapses)."""
    run = granflow.run("rectangle-rigid", [*COLUMN, "time.t_end=0.03",
                                           "time.output_times=[0.03]"],
                       out=tmp_path / "run", progress=False)
    assert run.summary.status == "completed"
    s = run.fields(0.03)["mobilisation"]
    assert len(s) == len(run.fields(0.03).triangles) and 0 < s.max() <= 1
    assert (run.fields(0.0)["mobilisation"] == 0).all()
    fraction = run.diagnostics["mobilised_fraction"]
    assert fraction.iloc[0] < fraction.iloc[-1]
