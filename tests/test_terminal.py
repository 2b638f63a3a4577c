"""What a run prints is granflow's own: a short collapse through every path that reads the
volume on a wall (two materials, a hysteretic friction, Picard's frozen wall load) prints
nothing else on stdout or stderr (NGSolve's compiler once printed a line per coefficient
it did not know, 16 to 80 per run)."""

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


def test_a_short_collapse_prints_only_granflows_lines(tmp_path: Path,
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)          # the report names the run's folder from here
    out = Path("run")
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, "-m", "granflow", *CASE, "--out", str(out)],
                          capture_output=True, text=True, timeout=300, env=env, cwd=tmp_path)
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
