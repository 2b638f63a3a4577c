"""Resume is exact and extends finished runs: a coarse two-material erodible collapse (with
remeshes after the checkpoint) killed right after a checkpoint resumes to the uninterrupted
run's result bit for bit; a finished run is extended to a later t_end; a run killed before
its first checkpoint and keys that would change the problem are refused with one line.
"""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

import granflow
import granflow.runner as runner
from granflow.cli import main
from granflow.io.checkpoint import write_checkpoint
from granflow.io.run_dir import RunDir
from granflow.io.run_state import SimulationState

# 2 cm layer of its own friction angle, one cell across, 5 cm mesh: about 200 triangles,
# 156 steps, remeshes at steps 113 and 123 (about 7 s)
# (isotropic cells and a tight tolerance: the remeshes come after the checkpoint; Anderson's
# mixing as in the scenario)
ERODIBLE = {"mesh.size": 0.05, "geometry.erodible_thickness": 0.02, "mesh.layer_cells": 1,
            "mesh.layer_aspect": 1.0, "numerics.tol": 3e-5, "numerics.anderson_depth": 3,
            "layer.friction_angle_deg": 30.0, "time.t_end": 0.15,
            "time.output_times": [0.1, 0.15], "output.checkpoint_every": 10,
            "time.dt_max_slow": None}          # steps of at most dt_max: the steps above
KILLED_AT = 110        # a checkpoint before the remeshes


def summary(root: Path) -> dict:
    return json.loads((root / "summary.json").read_text())


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The uninterrupted run, and a copy of its folder taken right after the checkpoint of
    step KILLED_AT: what kill -9 at that moment leaves (status "running")."""
    folder = tmp_path_factory.mktemp("resume")
    run_killed_at(KILLED_AT, ERODIBLE, folder / "reference", folder / "killed")
    return folder / "reference", folder / "killed"


def run_killed_at(step: int, overrides: dict[str, Any], out: Path, killed: Path,
                  scenario: str = "trapezoid-erodible", progress: bool | None = None) -> None:
    """``scenario`` with ``overrides`` into ``out``, and into ``killed`` a copy of its
    folder taken right after the checkpoint of ``step``: what kill -9 at that moment leaves
    (status "running")."""
    with pytest.MonkeyPatch.context() as patch:
        def copy_at(run_dir: RunDir, state: SimulationState) -> Path:
            path = write_checkpoint(run_dir, state)
            if state.step == step:
                shutil.copytree(run_dir.root, killed,
                                ignore=shutil.ignore_patterns(".granflow.lock"))
            return path
        patch.setattr(runner, "write_checkpoint", copy_at)
        granflow.run(scenario, overrides, out, progress=progress)


def test_a_killed_erodible_run_resumes_to_the_same_result(uninterrupted,
                                                          tmp_path: Path) -> None:
    reference, killed = uninterrupted
    killed = Path(shutil.copytree(killed, tmp_path / "killed"))
    assert summary(killed)["status"] == "running"
    (killed / "fields" / ".fields.pvd.x1y2z3a4.tmp.pvd").write_text("left by the kill")
    resumed = granflow.resume(killed)
    first, again = summary(reference), summary(killed)
    assert again["status"] == "completed" and again["resumed"] is True
    assert first["two_materials"] is True and first["remeshes"] >= 2
    # the same arithmetic: every diagnostics row equal (to round-off: here exactly)
    a, b = pd.read_csv(reference / "diagnostics.csv"), resumed.diagnostics
    assert len(a) == len(b) == first["steps"]
    pd.testing.assert_frame_equal(a, b, rtol=1e-12, atol=1e-15)
    for key in ("runout_m", "remeshes", "column_front_m", "layer_displaced_area_m2",
                "erosion_depth_max_m", "layer_area_drift", "nonlinear_iterations"):
        assert again[key] == pytest.approx(first[key], rel=1e-12, abs=1e-15), key
    assert not (killed / "fields" / ".fields.pvd.x1y2z3a4.tmp.pvd").exists()


def test_a_finished_run_is_extended_to_a_later_t_end(uninterrupted, tmp_path: Path) -> None:
    reference, _ = uninterrupted
    short = dict(ERODIBLE, **{"time.t_end": 0.06, "time.output_times": [0.05]})
    root = granflow.run("trapezoid-erodible", short, tmp_path / "run").root
    code, err = cli("resume", root)
    assert code == 2 and "already finished" in err and "time.t_end" in err
    extended = granflow.resume(root, {"time.t_end": 0.1, "time.output_times": [0.05, 0.1]})
    again = summary(root)
    assert again["status"] == "completed" and again["t_final"] == pytest.approx(0.1)
    assert again["resumed"] is True and extended.config.time.t_end == 0.1   # config.toml
    diagnostics = extended.diagnostics
    assert diagnostics["t"].is_monotonic_increasing and len(diagnostics) == again["steps"]
    assert (root / "profiles" / "free_surface_t0.100.csv").is_file()
    # the same flow as the uninterrupted run at t = 0.1: only the step cut at 0.06 differs
    first = pd.read_csv(reference / "diagnostics.csv").set_index("t")
    at = first.index[abs(first.index - 0.1) < 1e-9][0]
    assert abs(diagnostics["front_x"].iloc[-1] - first.loc[at, "front_x"]) < 1e-4
    assert abs(diagnostics["kinetic_energy"].iloc[-1] / first.loc[at, "kinetic_energy"] - 1
               ) < 1e-3


def cli(*args: str | Path) -> tuple[int, str]:
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main([str(a) for a in args])
    lines = [line for line in err.getvalue().splitlines() if "note:" not in line]
    assert len(lines) <= 1 and "Traceback" not in err.getvalue(), lines
    return code, "".join(lines)


@pytest.mark.parametrize("overrides, why", [
    (["--set", "mesh.size=0.04"], "mesh.size cannot change when a run is resumed"),
    (["--set", "layer.friction_angle_deg=25"], "layer.friction_angle_deg cannot change"),
    (["--set", "time.t_end=0.1", "--set", "time.output_times=[0.1]"],
     "must be later than the run's time"),
    (["--set", "time.output_times=[0.02, 0.1, 0.15]"], "may only add times after"),
], ids=["mesh", "material", "earlier-t-end", "past-output-time"])
def test_a_resume_that_would_change_the_problem_is_one_line(uninterrupted, tmp_path: Path,
                                                            overrides: list[str],
                                                            why: str) -> None:
    _, killed = uninterrupted
    root = tmp_path / "copy"
    shutil.copytree(killed, root)
    before = (root / "config.toml").read_text()
    code, err = cli("resume", root, *overrides)
    assert code == 2 and why in err
    assert (root / "config.toml").read_text() == before


def test_a_run_killed_before_its_first_checkpoint_says_how_to_restart(uninterrupted,
                                                                      tmp_path: Path) -> None:
    _, killed = uninterrupted
    root = tmp_path / "early"
    shutil.copytree(killed, root)
    shutil.rmtree(root / "checkpoint")
    code, err = cli("resume", root)
    assert code == 2 and "before its first checkpoint" in err
    assert f"granflow run {root / 'config.toml'} --out {root} --force" in err


# A coarse nonlocal rectangle (glass beads' constants), checkpointed every 10 steps: the
# fluidity's own system is solved with the flow at every accepted step
NONLOCAL = {"material.rheology": "nonlocal", "material.friction_angle_deg": 20.9,
            "material.grain_diameter": 0.00053, "boundary.normal_load": "reaction",
            "mesh.size": 0.04, "time.t_end": 0.06, "time.output_times": [0.06],
            "output.checkpoint_every": 10}
NONLOCAL_KILLED_AT = 20


def test_a_nonlocal_run_continued_past_a_checkpoint_equals_it_resumed(tmp_path: Path) -> None:
    """The run that goes on after writing its checkpoint and the run resumed from that
    checkpoint are the same run: every summary figure (but the wall time and the resume's
    own flag) and the free surface to the digit (the fluidity's factorisation, too, starts
    afresh after a checkpoint)."""
    run_killed_at(NONLOCAL_KILLED_AT, NONLOCAL, tmp_path / "continued", tmp_path / "killed",
                  scenario="rectangle-rigid", progress=False)
    resumed = granflow.resume(tmp_path / "killed", progress=False)
    first = summary(tmp_path / "continued")
    assert first["status"] == "completed" and first["steps"] > 2 * NONLOCAL_KILLED_AT
    assert_resumed_is_uninterrupted(resumed, tmp_path / "continued")


def assert_resumed_is_uninterrupted(resumed: granflow.Run, uninterrupted: Path) -> None:
    """Every summary figure but the wall time and the resume's own flag, every diagnostics
    row and the final free surface: the resumed run is the uninterrupted one to the digit."""
    first, again = summary(uninterrupted), summary(resumed.root)
    assert again["resumed"] is True
    own = {"wall_time_s", "resumed"}
    assert {k: v for k, v in again.items() if k not in own} == {
        k: v for k, v in first.items() if k not in own}
    pd.testing.assert_frame_equal(pd.read_csv(uninterrupted / "diagnostics.csv"),
                                  resumed.diagnostics, rtol=0, atol=0)
    surface = Path("profiles") / "free_surface_final.csv"
    assert (resumed.root / surface).read_bytes() == (uninterrupted / surface).read_bytes()


# The erodible set-up above with a packing fraction: a dense column (phi_0 = 0.62) over a
# loose layer (0.58), the mass kept by the free-surface fix, phi carried through remeshes
PACKING = {**ERODIBLE, "material.packing": "critical-state", "layer.packing": "critical-state",
           "layer.density": 1450.0, "output.progress": False}
PACKING_KILLED_AT = 130      # a checkpoint after the first remesh (step 123), before the second


def test_a_killed_packing_run_resumes_to_the_same_result(tmp_path: Path) -> None:
    """The run killed right after a checkpoint that follows a remesh, resumed, is the
    uninterrupted run: every summary figure (but the wall time and the resume's own flag,
    the packing's range and mass error among them), every diagnostics row and the free
    surface to the digit."""
    run_killed_at(PACKING_KILLED_AT, PACKING, tmp_path / "uninterrupted", tmp_path / "killed")
    killed_at = pd.read_csv(tmp_path / "killed" / "diagnostics.csv")["t"].iloc[-1]
    assert summary(tmp_path / "killed")["status"] == "running"
    resumed = granflow.resume(tmp_path / "killed", progress=False)
    first = summary(tmp_path / "uninterrupted")
    assert first["status"] == "completed"
    remeshed = np.array(first["remesh_times_s"])
    assert (remeshed <= killed_at).any() and (remeshed > killed_at).any()   # before, after
    assert first["packing_min"] < 0.58 + 1e-3 and first["packing_max"] > 0.62 - 1e-3
    assert first["volume_relative_error"] != 0.0              # the packing changed
    assert_resumed_is_uninterrupted(resumed, tmp_path / "uninterrupted")
