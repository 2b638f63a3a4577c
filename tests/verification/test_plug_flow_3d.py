"""Rung 11: the plug flow of the paper's section 4 in 3D (periodic along the slope and
across it) against the independent 1D solver of (4.1).

The coarse cell of Table 1 (eps = 1e-6, dt = 2.5e-2 s, dZ = 0.25 m) on a box of 2 x 2
columns of structured tetrahedra. Acceptance as the 2D layer's: the error is at most twice
the paper's (the paper's 2D value, 0.0125); the flow stays along the slope.
"""

import ngsolve as ngs
import pytest

from granflow.config import ConfigError, load_config
from granflow.scenarios.plug_flow_3d import build_plug_flow_3d
from granflow.verify import paper_table, run_cell

DT, DZ = 2.5e-2, 0.25


@pytest.fixture(scope="module")
def layer():
    config = load_config("plug-flow", ["geometry.dimension=3", f"time.dt={DT!r}",
                                       f"mesh.size={DZ!r}", f"geometry.length={2 * DZ!r}",
                                       "time.output_times=[]"])
    problem = build_plug_flow_3d(config)
    result = problem.simulation.run()
    return problem, result


def test_3d_plug_flow_against_the_1d_solver(layer) -> None:
    problem, result = layer
    assert result.status == "completed", result.message
    paper = next(r["error"] for r in paper_table(1)
                 if r.get("eps", 1e-6) == 1e-6 and r["dt"] == DT and r["dZ"] == DZ)
    error = problem.velocity_error(result.t_final)
    assert 0 < error <= 2 * paper


def test_3d_plug_flow_is_the_2d_layer(layer) -> None:
    """Uniform across the slope, the 3D layer's error is the 2D layer's within 1 %."""
    problem, result = layer
    error_2d = run_cell(1e-6, DT, DZ, extra=("numerics.linearization=newton",))[0]
    assert problem.velocity_error(result.t_final) == pytest.approx(error_2d, rel=0.01)


def test_3d_plug_flow_stays_along_the_slope(layer) -> None:
    """The across (Y) and bed-normal (Z) velocities stay below 1e-6 of the along one (L2)."""
    problem, _ = layer
    u = problem.solver.velocity
    along, across, normal = (ngs.Integrate(u[i] * u[i], problem.mesh) for i in range(3))
    assert max(across, normal) <= 1e-12 * along


@pytest.mark.parametrize("setting, words", [
    ("material.rheology=nonlocal", "not verified in 3D"),
    ("material.friction=hysteretic", "not verified in 3D"),
    ("numerics.mesh_velocity=vertical", "runs on a fixed mesh"),
    ("numerics.method=augmented-lagrangian", "2 x 2 tensors")])
def test_3d_layer_refuses_what_is_not_verified(setting: str, words: str) -> None:
    with pytest.raises(ConfigError, match=words):
        load_config("plug-flow", ["geometry.dimension=3", setting])
