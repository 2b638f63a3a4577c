"""The collapse over an erodible layer (configuration III) and on a sloping bed, CI size:
coarse meshes, short times."""

import numpy as np
import pytest

from granflow.config import load_config
from granflow.diagnostics.state import flowing_cells
from granflow.fem.sampling import cell_means, triangles
from granflow.geometry.mesh import END, signed_areas
from granflow.scenarios.column import build_column

COARSE = ["mesh.size=0.05", "time.dt=1e-3", "numerics.tol=1e-3", "time.output_times=[]",
          "time.adaptive=false", "time.stop_at_rest=false"]


@pytest.fixture(scope="module")
def short_erodible(run_short_column):
    return run_short_column("trapezoid-erodible", [*COARSE, "time.t_end=0.03"])


def test_layer_is_resolved_by_the_requested_cells() -> None:
    """mesh.layer_cells = 2: the end of the 5 mm layer is split into 2 edges; 4 gives 4."""
    for cells in (2, 4):
        problem = build_column(load_config("trapezoid-erodible",
                                           [*COARSE, f"mesh.layer_cells={cells}"]))
        chain = problem.mover.chain
        assert np.sum(chain.labels() == chain.index[END]) == cells


def test_short_erodible_run_stays_valid(short_erodible) -> None:
    problem, result, area0 = short_erodible
    assert result.status == "completed", result.message
    assert signed_areas(problem.mesh).min() > 0
    xy = problem.mesh.ngmesh.Coordinates()
    assert xy[:, 1].min() >= 0.0 and xy[:, 0].min() >= 0.0
    assert xy[:, 0].max() == pytest.approx(problem.config.geometry.bed_length, abs=1e-12)
    assert abs(problem.mover.area() - area0) / area0 < 1e-12


def test_far_layer_stays_at_rest(short_erodible) -> None:
    """The undisturbed layer beyond the flow (X > 0.5 m) stays below 1 mm/s (the flowing
    threshold) while the column collapses: the frictionless end wall holds it."""
    problem, _, _ = short_erodible
    import ngsolve as ngs

    speed, _ = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))
    xy = problem.mesh.ngmesh.Coordinates()
    centroid_x = xy[triangles(problem.mesh)].mean(axis=1)[:, 0]
    far = centroid_x > 0.5
    assert far.sum() > 20
    assert speed[far].max() < 1e-3
    flags, _ = flowing_cells(problem.mesh, problem.solver.velocity)
    assert flags.any() and not flags[far].any()


def test_short_run_on_a_20_degree_slope() -> None:
    """Gravity in bed coordinates (2.1a): on a 20 deg slope the rectangle moves downslope
    faster than on a horizontal bed over the same 0.05 s."""
    fronts = {}
    for slope in (0.0, 20.0):
        problem = build_column(load_config("rectangle-rigid", [
            *COARSE, "mesh.size=0.04", "time.t_end=0.05", f"geometry.slope_deg={slope}"]))
        result = problem.simulation.run()
        assert result.status == "completed", result.message
        assert signed_areas(problem.mesh).min() > 0
        fronts[slope] = problem.mesh.ngmesh.Coordinates()[:, 0].max()
    assert fronts[20.0] > fronts[0.0] > 0.2
