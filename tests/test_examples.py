"""The examples in examples/ run (coarse and short, with --quick) and write what they say."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("script, expected", [
    ("collapse.py", ["free_surfaces.png", "summary.json"]),
    ("parameter_study.py", ["study.csv", "study.png", "h0.2/summary.json"]),
    ("compare_rheologies.py", ["rheologies.png", "mu-i/summary.json"]),
    ("erodible_layer.py", ["erosion_depths.png", "looser-layer/plots/erosion.png"]),
])
def test_example_runs(script: str, expected: list[str], tmp_path: Path) -> None:
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, str(EXAMPLES / script), "--quick", "--out", str(out)],
                          capture_output=True, text=True, timeout=900,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr
    for name in expected:
        assert (out / name).is_file(), f"{script} did not write {name}"
    assert "Traceback" not in done.stderr
    assert "None" not in done.stdout, done.stdout          # every number printed as one
