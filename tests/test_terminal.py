"""What a run prints is granflow's own: a short collapse through every path that reads the
volume on a wall (two materials, a hysteretic friction, Picard's frozen wall load) prints
nothing else on stdout or stderr (NGSolve's compiler once printed a line per coefficient
it did not know, 16 to 80 per run); nor do long runs (with ``-m slow``), a run of 200
remeshes and the default erodible collapse (NGSolve's profiler warned once its table of
timers was full: "no more timer available (FESpace), reusing last one")."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from granflow.io.report import final_lines
from granflow.io.run_dir import RunDir

CASE = ["run", "trapezoid-erodible", "--set", "mesh.size=0.04", "--set", "time.t_end=0.005",
        "--set", "time.output_times=[0.0025]", "--set", "layer.friction_angle_deg=20",
        "--set", "material.friction=hysteretic"]
PROGRESS = re.compile(r"\s*\d+%\|.*t=[\d.]+/[\d.]+ s.*")     # the progress bar (tqdm)


# a step whose solve fails on a mesh below 0.99 in quality (all of them) is retried on a new
# one: 261 remeshes in 0.2 s of a coarse rectangle (18 s of processor time), where NGSolve
# printed "no more timer available (lff_from_py), reusing last one"
REMESHING = ["run", "rectangle-rigid", "--set", "mesh.size=0.04", "--set",
             "numerics.max_iterations=3", "--set", "mesh.failure_remesh_quality=0.99",
             "--set", "time.t_end=0.2", "--set", "time.output_times=[]"]


def test_a_short_collapse_prints_only_granflows_lines(tmp_path: Path,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    prints_only_granflows_lines(CASE, tmp_path, monkeypatch)


@pytest.mark.slow
def test_a_run_of_200_remeshes_prints_only_granflows_lines(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The default suite's longest check (about 20 s of processor time): with ``-m slow``."""
    summary = prints_only_granflows_lines(REMESHING, tmp_path, monkeypatch)
    assert summary["remeshes"] >= 200


@pytest.mark.slow
@pytest.mark.timeout(3600)
def test_the_default_erodible_collapse_prints_only_granflows_lines(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The default trapezoid-erodible to its end (1,047 steps and 94 remeshes, 15 min)."""
    summary = prints_only_granflows_lines(["run", "trapezoid-erodible"], tmp_path, monkeypatch)
    assert summary["status"] in ("completed", "stopped") and summary["remeshes"] > 50


def prints_only_granflows_lines(case: list[str], tmp_path: Path,
                                monkeypatch: pytest.MonkeyPatch) -> dict:
    """Run ``granflow CASE`` and check that every line it printed is granflow's."""
    monkeypatch.chdir(tmp_path)          # the report names the run's folder from here
    out = Path("run")
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "-m", "granflow", *case, "--out", str(out)],
                          capture_output=True, text=True, timeout=3600, env=env, cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    report = final_lines(RunDir.summary(out), out)
    for line in done.stdout.splitlines():
        assert line.startswith(("granflow: ", "drawing the figures into ")) or \
            line in report, f"a line granflow did not print: {line!r}"
    assert report[0] in done.stdout
    assert str(tmp_path) not in done.stdout, "a path printed absolute among relative ones"
    assert "drawing the figures into run/plots" in done.stdout
    for line in re.split(r"[\r\n]+", done.stderr):
        assert not line.strip() or line.startswith("granflow: note: ") or \
            PROGRESS.fullmatch(line), f"a line granflow did not print: {line!r}"
    return RunDir.summary(out)
