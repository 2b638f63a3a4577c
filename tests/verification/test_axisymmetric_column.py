"""Axisymmetric columns (``geometry.axisymmetric``): a short cylinder collapse on a coarse
mesh keeps its revolved volume, its axis and its mass at rest when the yield stress holds the
load, and an unchanged plane-strain column gives the same as a plane run."""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np
import pytest

from granflow.config import load_config
from granflow.fem.sampling import cell_means, vertex_samples
from granflow.geometry.mesh import WALL
from granflow.scenarios.column import build_column

COARSE = ["mesh.size=0.02", "time.output_times=[0.05]"]


@pytest.fixture(scope="module")
def short_cylinder(run_short_column):
    return run_short_column("cylinder-rigid", [*COARSE, "time.t_end=0.1"])


def test_a_short_cylinder_collapse_keeps_its_revolved_volume(short_cylinder) -> None:
    problem, result, volume0 = short_cylinder
    assert result.status == "completed", result.message
    assert volume0 == pytest.approx(math.pi * 0.10**2 * 0.14, rel=1e-12)   # pi r0^2 h0
    assert abs(problem.mover.area() - volume0) / volume0 < 1e-12
    xy = problem.mesh.ngmesh.Coordinates()
    assert xy[:, 0].max() > 0.12                  # the front has moved out from r0 = 0.1 m


def test_the_axis_stays_the_axis(short_cylinder) -> None:
    """Nodes on the axis keep r = 0, and the radial velocity vanishes there (strongly)."""
    problem, _, _ = short_cylinder
    on_axis = problem.mover.chain.vertices(WALL)
    xy = problem.mesh.ngmesh.Coordinates()
    assert on_axis.size > 2 and np.all(xy[on_axis, 0] == 0.0)
    at_vertices = vertex_samples(problem.mesh, problem.solver.velocity)
    assert np.abs(at_vertices[on_axis, 0]).max() < 1e-14
    assert np.abs(at_vertices[on_axis, 1]).max() > 1e-3   # while the axis itself moves down


def test_revolved_volume_drift_without_the_correction_is_small_but_visible() -> None:
    """The same fix as in plane strain, on the volume of revolution (not the area, which an
    axisymmetric flow does not conserve)."""
    problem = build_column(load_config("cylinder-rigid", [
        *COARSE, "time.t_end=0.05", "numerics.volume_correction=false"]))
    volume0 = problem.mover.area()
    assert problem.simulation.run().status == "completed"
    drift = abs(problem.mover.area() - volume0) / volume0
    assert 1e-7 < drift < 1e-2


@pytest.mark.parametrize("scenario, extra", [("cylinder-rigid", []),
                                             ("rectangle-rigid", ["geometry.width=0.1"])])
def test_a_column_whose_yield_stress_holds_its_load_stays_at_rest(scenario: str,
                                                                  extra: list[str]) -> None:
    """Friction angle 60 degrees: the column creeps as the regularisation (2.13) lets it and
    no faster, in r-z as in plane strain. Below the yield stress the regularised law gives
    strain rates of order eps (1e-6 1/s), so speeds of order eps h0 (1.4e-7 m/s) and
    displacements of order eps h0 t_end (7e-9 m in 0.05 s); the bounds are 10 times those,
    and a column that yielded would move at about sqrt(g h0), 1 m/s. The iteration's velocity
    floor is the creep scale, not the flowing threshold (1 mm/s, at which (3.2) stops anywhere
    below 3e-7 m/s and round-off alone, the LU or MKL's code path, moved these speeds from
    3e-7 to 2e-6 m/s): the creep is then resolved, the same with PARDISO in any code path
    and with UMFPACK to 15 digits. Measured 3.19e-7 and 8.19e-8 m/s (2.3 and 0.6 eps h0),
    displacements 1.63e-8 and 3.6e-9 m; with eps 10 times larger, 8 and 10 times more
    (the bed's eps_friction 10 times larger: 1.6 and 1 times)."""
    problem = build_column(load_config(scenario, [
        *extra, *COARSE, "time.t_end=0.05", "material.friction_angle_deg=60",
        "boundary.bed_friction_deg=60", "time.stop_at_rest=false",
        "numerics.linearization=newton", "numerics.max_iterations=50",
        "numerics.velocity_floor=1e-7"]))
    config = problem.config
    creep = config.numerics.eps * config.geometry.height      # m/s
    xy0 = problem.mesh.ngmesh.Coordinates().copy()
    assert problem.simulation.run().status == "completed"
    speed, _ = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))
    assert speed.max() < 10 * creep
    moved = np.abs(problem.mesh.ngmesh.Coordinates() - xy0).max()
    assert moved < 10 * creep * config.time.t_end


def test_axisymmetric_settings_are_refused_where_they_mean_nothing() -> None:
    from granflow.config import ConfigError

    for extra, word in [(["geometry.slope_deg=10"], "geometry.slope_deg"),
                        (["boundary.channel_width=0.1"], "boundary.channel_width"),
                        (["numerics.linearization=primal-dual"], "primal-dual"),
                        (["numerics.method=augmented-lagrangian"], "augmented-lagrangian"),
                        (["boundary.wall_friction_deg=20"], "symmetry axis")]:
        with pytest.raises(ConfigError, match=word):
            load_config("cylinder-rigid", extra)
    with pytest.raises(ConfigError, match="geometry.axisymmetric"):
        load_config("plug-flow", ["geometry.axisymmetric=true"])


def test_a_cylinder_over_an_erodible_layer_runs_and_keeps_its_volume() -> None:
    """cylinder-erodible on a coarse mesh, with its surface tension: the layer reaches
    r = 0.2 m (its far end is a frictionless wall), the revolved volume is kept."""
    problem = build_column(load_config("cylinder-erodible", [
        "mesh.size=0.02", "mesh.layer_cells=1", "geometry.bed_length=0.2", "time.t_end=0.03",
        "time.output_times=[0.03]"]))
    volume0 = problem.mover.area()
    assert volume0 == pytest.approx(math.pi * 0.1**2 * 0.14 + math.pi * 0.2**2 * 0.005,
                                    rel=1e-12)   # the cylinder and the layer's disc
    assert problem.simulation.run().status == "completed"
    assert abs(problem.mover.area() - volume0) / volume0 < 1e-12
