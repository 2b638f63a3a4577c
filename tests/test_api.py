"""The Python API: granflow.run / granflow.load / granflow.Config on a coarse, short
collapse, checked against the files the run wrote and against the command line."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import granflow
from granflow.config import ConfigError

COARSE = {"mesh.size": 0.05, "time.t_end": 0.06, "time.output_times": [0.03, 0.06]}


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> granflow.Run:
    out = tmp_path_factory.mktemp("api") / "rect"
    return granflow.run("rectangle-rigid", overrides=COARSE, out=out)


def test_run_returns_the_summary_the_run_wrote(run: granflow.Run) -> None:
    written = json.loads((run.root / "summary.json").read_text())
    summary = run.summary
    assert summary.ok and summary.status == "completed"
    assert summary.t_final == pytest.approx(0.06)
    assert summary.runout_m == written["runout_m"] and summary.runout_m > 0.2
    assert summary.steps == written["steps"] > 10
    assert summary.extra["n_triangles"] == written["n_triangles"]
    assert run.config.mesh.size == 0.05 and run.config.geometry.width == 0.2


def test_diagnostics_surfaces_and_fields_match_the_files(run: granflow.Run) -> None:
    diagnostics = run.diagnostics
    assert len(diagnostics) == run.summary.steps
    assert diagnostics["t"].iloc[-1] == pytest.approx(0.06)
    surfaces = run.surfaces
    assert set(surfaces["kind"]) == {"free_surface", "interface"}
    assert sorted(set(surfaces["t"])) == pytest.approx([0.03, 0.06])
    at_end = surfaces[(surfaces["kind"] == "free_surface") & (surfaces["t"] == 0.06)]
    assert at_end["x"].max() == pytest.approx(run.summary.runout_m, abs=1e-9)
    assert run.output_times == pytest.approx([0.0, 0.03, 0.06])
    fields = run.fields(0.03)
    assert fields.t == pytest.approx(0.03) and fields.points.shape[1] == 2
    assert fields["velocity"].shape == (len(fields.points), 2)
    assert np.abs(fields["velocity"]).max() > 0.01       # the column is moving at 0.03 s
    with pytest.raises(ValueError, match="snapshots at"):
        run.fields(0.5)


def test_load_gives_the_same_object_and_plots(run: granflow.Run) -> None:
    again = granflow.load(run.root)
    assert again.summary == run.summary
    assert again.diagnostics.equals(run.diagnostics)
    ax = again.plot.free_surfaces()
    assert len(ax.lines) == 2 and ax.get_xlabel() == "x (m)"


def test_config_load_and_set_validate(tmp_path: Path) -> None:
    config = granflow.Config.load("rectangle-rigid").set("geometry.height", 0.2)
    assert config.geometry.height == 0.2
    assert granflow.Config.load("rectangle-rigid").geometry.height != 0.2   # a new object
    with pytest.raises(ConfigError, match="geometry.height"):
        config.set("geometry.height", -1.0)
    with pytest.raises(ConfigError, match="unknown"):
        config.set("geometry.hieght", 0.2)


def test_a_config_object_runs_like_the_command_line(tmp_path: Path) -> None:
    """The same case through the API (a Config) and the CLI: identical results."""
    config = granflow.Config.load("rectangle-rigid")
    for key, value in COARSE.items():
        config = config.set(key, value)
    by_api = granflow.run(config, out=tmp_path / "api")
    args = [a for k, v in COARSE.items() for a in ("--set", f"{k}={v}")]
    done = subprocess.run([sys.executable, "-m", "granflow", "run", "rectangle-rigid", *args,
                           "--out", str(tmp_path / "cli"), "--quiet"], capture_output=True,
                          text=True, timeout=600, env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr
    by_cli = granflow.load(tmp_path / "cli")
    assert by_api.summary.runout_m == by_cli.summary.runout_m
    assert by_api.summary.steps == by_cli.summary.steps


def test_profiles_carry_their_time_and_units(run: granflow.Run) -> None:
    """Every profile file ends with its time; units.json names each column's unit; the
    reader finds the output times and the final state."""
    from granflow.io import profiles

    found = profiles.list_profiles(run.root, "free_surface")
    assert [p.label for p in found] == ["t0.030", "t0.060", "final"]
    for p in found:
        data = p.read()
        assert list(data) == ["x", "z", "t"] and np.all(data["t"] == p.t)
    assert found[-1].t == pytest.approx(run.summary.t_final)
    units = json.loads((run.root / "profiles" / "units.json").read_text())
    assert units["x"] == "m" and units["u_x"] == "m/s" and units["t"] == "s"
    sections = profiles.profile_at(run.root, "velocity_sections", 0.03)
    assert sections is not None and set(sections) == {"section_x", "z", "u_x", "u_z", "t"}
    assert profiles.surface_distances(run.root, run.root)[0.03] == (0.0, 0.0)


def test_a_run_needs_its_folder_locked(tmp_path: Path) -> None:
    from granflow.io.run_dir import RunDir, RunDirError
    from granflow.runner import run_simulation

    run_dir = RunDir.create(tmp_path / "unlocked")
    with pytest.raises(RunDirError, match="must be locked"):
        run_simulation(granflow.Config.load("rectangle-rigid"), run_dir)


def test_resume_refuses_a_finished_run(run: granflow.Run) -> None:
    from granflow.io.run_dir import RunDirError

    with pytest.raises(RunDirError, match="already finished"):
        granflow.resume(run.root)


def test_a_cylinder_runs_from_the_api_with_its_measures_in_r(tmp_path: Path) -> None:
    cylinder = granflow.run("cylinder-rigid", overrides={
        "mesh.size": 0.03, "time.t_end": 0.05, "time.output_times": [0.05]},
        out=tmp_path / "cyl")
    summary = cylinder.summary
    assert summary.ok and summary.runout_m > 0.1
    assert summary.extra["initial_volume_m3"] == pytest.approx(np.pi * 0.1**2 * 0.14)
    assert summary.extra["axis_height_m"] == summary.extra["wall_height_m"] < 0.14
    assert cylinder.diagnostics["volume"].iloc[0] == pytest.approx(np.pi * 0.1**2 * 0.14)
    assert cylinder.plot.free_surfaces().get_xlabel() == "r (m)"
    assert (cylinder.root / "plots" / "free_surface.png").is_file()
    fields = cylinder.fields(0.05)         # the hoop stress of r-z: compressive like the rest
    assert np.all(fields["stress_hoop"] < 0) and "stress_hoop" in repr(fields)


def test_a_layer_of_its_own_material_reports_its_entrainment(tmp_path: Path) -> None:
    """A column over a looser, weaker layer from the API: the entrainment columns of the
    diagnostics, the erosion profiles, the markers with their origins, the figure."""
    run = granflow.run("trapezoid-erodible", overrides={
        "mesh.size": 0.05, "geometry.erodible_thickness": 0.01, "geometry.bed_length": 0.5,
        "time.t_end": 0.04, "time.output_times": [0.02], "surface_tension.enabled": False,
        "layer.friction_angle_deg": 20.0, "layer.density": 1400.0}, out=tmp_path / "layer")
    assert run.summary.ok and run.summary.extra["two_materials"] is True
    diagnostics = run.diagnostics
    for column in ("layer_mobilised_area", "layer_displaced_area", "erosion_front_x",
                   "column_front_x", "erosion_depth_max", "layer_area_drift"):
        assert column in diagnostics
    assert diagnostics["column_front_x"].iloc[0] == pytest.approx(0.297 - 0.01 / np.tan(
        np.radians(70)), abs=1e-3)                   # the front face at the layer's top
    assert abs(run.summary.extra["layer_area_drift"]) < 0.01
    erosion = run.erosion
    assert sorted(set(erosion["t"])) == pytest.approx([0.02, 0.04])
    assert erosion["depth"].between(0, 0.01).all()
    markers = run.profile("layer_markers")
    assert {"x", "z", "x0", "z0", "travel", "speed"} <= set(markers)
    assert markers["z0"].max() < 0.01 and len(markers) > 500
    assert run.profile("layer_line", 0.02)["z"].min() > 0
    with pytest.raises(KeyError, match="no 'nothing' profile"):
        run.profile("nothing")
    assert (run.root / "plots" / "erosion.png").is_file()
    start = run.fields(0.0)["layer_fraction"]          # the indicator, for ParaView: the
    assert set(np.unique(start)) == {0.0, 1.0}          # first mesh follows the interface
    assert np.count_nonzero((run.fields(0.04)["layer_fraction"] % 1) > 0) > 0
