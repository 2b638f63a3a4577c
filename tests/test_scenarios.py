"""Every built-in scenario smoke-runs through the CLI on a coarse mesh for a short time."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from granflow.config import load_config
from granflow.geometry.scene import build_scene

SHORT = {
    "plug-flow": ["mesh.size=0.5", "time.dt=0.05", "time.t_end=0.1", "time.output_times=[0.1]",
                  "numerics.eps=1e-2"],
    "trapezoid-rigid": ["mesh.size=0.05", "time.dt=2e-3", "numerics.tol=1e-3",
                        "time.t_end=0.04", "time.output_times=[0.02,0.04]"],
    "rectangle-rigid": ["mesh.size=0.04", "time.t_end=2e-3", "time.dt_max=1e-3",
                        "time.output_times=[2e-3]"],
    "trapezoid-erodible": ["mesh.size=0.05", "time.dt=1e-3", "numerics.tol=1e-3",
                           "time.t_end=0.005", "time.output_times=[]"],
    "incline-mu-i": ["mesh.size=0.0025", "time.dt=0.01", "time.t_end=0.05",
                     "time.output_times=[0.05]"],
    "incline-nonlocal": ["time.t_end=0.05", "time.output_times=[0.05]"],
    "incline-to-floor": ["mesh.size=0.04", "time.t_end=0.01", "time.output_times=[0.01]"],
    "hillslope": ["mesh.size=0.08", "time.t_end=0.01", "time.output_times=[0.01]"],
    "slab": ["geometry.erodible_thickness=0.005", "time.t_end=0.02",
             "time.output_times=[0.02]"],
}


def run_cli(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "granflow", *args], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("scenario", sorted(SHORT))
def test_scenario_runs_and_writes_its_run_directory(tmp_path: Path, scenario: str) -> None:
    overrides = [a for s in SHORT[scenario] for a in ("--set", s)]
    out = tmp_path / "run"
    proc = run_cli(tmp_path, "run", scenario, *overrides, "--out", str(out), "--quiet")
    assert proc.returncode == 0, proc.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == "completed", summary["message"]
    assert summary["linear_solver"] in ("umfpack", "pardiso")   # the solver the run used
    for key in ("t_final", "steps", "rejected_steps", "nonlinear_iterations", "linear_solves",
                "wall_time_s", "stop_time_s", "runout_m", "volume_relative_error",
                "n_triangles", "n_dofs"):
        assert key in summary
    assert (out / "config.toml").exists()
    assert (out / "fields" / "fields.pvd").exists()
    header = (out / "diagnostics.csv").read_text().splitlines()[0]
    assert header.startswith("t,dt,iterations,front_x,wall_height,volume,kinetic_energy,"
                             "max_speed,flowing_fraction")   # the contract's columns first
    if scenario == "plug-flow":
        assert summary["velocity_relative_error_l2"] < 0.05
        assert (out / "profiles" / "velocity_t0.100.csv").exists()
    elif scenario == "trapezoid-rigid":
        assert summary["volume_relative_error"] < 1e-10
        for kind in ("free_surface", "velocity_sections", "interface"):
            assert (out / "profiles" / f"{kind}_t0.040.csv").exists()
        assert (out / "plots" / "free_surface.png").exists()
        with Image.open(out / "plots" / "speed.gif") as gif:   # one image per frame file
            frames = len(list((out / "frames").glob("frame_*.npz")))  # (Pillow merges repeats)
            assert 1 < gif.n_frames <= frames
    elif scenario == "slab":       # the slab over its layer: distances, the layer's moved depth
        assert 0.015 < summary["slab_distance_m"] == summary["runout_m"] < 0.02
        assert 0 < summary["layer_moved_depth_m"] <= 0.005
        assert (out / "profiles" / "slab_t0.020.csv").exists()
    elif scenario == "incline-nonlocal":    # thicker than h_stop: the steady flow is its own
        assert summary["reference"] == "steady" and summary["reference_note"] is None
    elif scenario in ("incline-to-floor", "hillslope"):     # a mass on a bed profile
        assert summary["volume_relative_error"] < 1e-10
        config = load_config(out / "config.toml")
        bed = build_scene(config.geometry, config.gate).bed
        surface = np.loadtxt(out / "profiles" / "free_surface_t0.010.csv", delimiter=",",
                             skiprows=1, usecols=(0, 1))
        assert bed.height(surface).min() > -1e-9           # on or above the bed
        assert (out / "plots" / "free_surface.png").exists()
    # the last accepted state as profiles/*_final.csv, whatever the output times
    assert summary["final_profiles_t"] == summary["t_final"]
    finals = sorted(p.name for p in (out / "profiles").glob("*_final.csv"))
    layer = (["erosion_depth_final.csv", "layer_line_final.csv", "layer_markers_final.csv"]
             if "erodible" in scenario else [])
    periodic = ("plug-flow", "incline-mu-i", "incline-nonlocal")
    assert finals == (["velocity_final.csv"] if scenario in periodic else
                      ["slab_final.csv"] if scenario == "slab" else
                      sorted(["free_surface_final.csv", "interface_final.csv",
                              "velocity_sections_final.csv", *layer]))
    if scenario == "trapezoid-rigid":   # t_end is the last output time: the same state
        for kind in ("free_surface", "velocity_sections", "interface"):
            assert ((out / "profiles" / f"{kind}_final.csv").read_text()
                    == (out / "profiles" / f"{kind}_t0.040.csv").read_text())
    if scenario in ("trapezoid-rigid", "rectangle-rigid"):   # the front is the surface's end
        rows = (out / "profiles" / "free_surface_final.csv").read_text().splitlines()[1:]
        assert max(float(r.split(",")[0]) for r in rows) == pytest.approx(summary["runout_m"],
                                                                         abs=1e-12)
    # `granflow plot` draws the same figures again from the files alone
    figures = sorted(p.name for p in (out / "plots").iterdir())
    assert figures
    for p in (out / "plots").iterdir():
        p.unlink()
    again = run_cli(tmp_path, "plot", str(out))
    assert again.returncode == 0, again.stderr
    assert sorted(p.name for p in (out / "plots").iterdir()) == figures


def test_a_run_says_once_which_sparse_solver_it_uses(tmp_path: Path) -> None:
    overrides = [a for s in SHORT["plug-flow"] for a in ("--set", s)]
    proc = run_cli(tmp_path, "run", "plug-flow", *overrides, "--set", "output.progress=false",
                   "--out", str(tmp_path / "run"))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count("sparse LU: ") == 1, proc.stdout
    used = json.loads((tmp_path / "run" / "summary.json").read_text())["linear_solver"]
    assert used.upper() in proc.stdout
