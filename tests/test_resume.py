"""Kill-safety of a run: SIGKILL at a random moment, then `granflow resume`, gives the
uninterrupted run's result exactly (it resumes from a checkpoint, where the uninterrupted
run's factorisations start afresh too); SIGINT, which checkpoints between two periodic
checkpoints, gives its stop time within 1 % and runout within 1 mm; a second run into a
running directory is refused."""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

# A 10 cm square column on a coarse mesh (64 triangles): at rest at t ~ 0.43 s, ~500 steps.
CASE = ["rectangle-rigid", "--set", "geometry.width=0.1", "--set", "geometry.height=0.1",
        "--set", "mesh.size=0.02", "--set", "time.t_end=1", "--set",
        "output.checkpoint_every=10", "--quiet"]
pytestmark = pytest.mark.slow   # two full runs to rest and their interrupted twins
ENV = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "MPLBACKEND": "Agg"}


def granflow(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "granflow", *map(str, args)], env=ENV,
                          capture_output=True, text=True, timeout=600)


def start(out: Path) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "granflow", "run", *CASE, "--out", str(out)],
                            env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_for_rows(out: Path, rows: int, proc: subprocess.Popen[str]) -> None:
    """Until diagnostics.csv has ``rows`` accepted steps (the process must still run)."""
    deadline = time.monotonic() + 300
    while time.monotonic() < deadline:
        assert proc.poll() is None, "the run ended before it could be interrupted"
        try:
            if (out / "diagnostics.csv").read_text().count("\n") > rows:
                return
        except FileNotFoundError:
            pass
        time.sleep(0.05)
    raise AssertionError("the run made no progress")


def summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


@pytest.fixture(scope="module")
def reference(tmp_path_factory: pytest.TempPathFactory) -> dict:
    out = tmp_path_factory.mktemp("reference") / "run"
    done = granflow("run", *CASE, "--out", out)
    assert done.returncode == 0, done.stderr
    result = summary(out)
    assert result["status"] == "stopped" and result["steps"] > 300
    return result


def final_front(out: Path) -> float:
    """The end of profiles/free_surface_final.csv: the front of the last accepted state."""
    rows = (out / "profiles" / "free_surface_final.csv").read_text().splitlines()[1:]
    return max(float(row.split(",")[0]) for row in rows)


def assert_same_result(resumed: dict, reference: dict) -> None:
    assert resumed["status"] == "stopped" and resumed["resumed"] is True
    assert resumed["stop_time_s"] == pytest.approx(reference["stop_time_s"], rel=0.01)
    assert abs(resumed["runout_m"] - reference["runout_m"]) < 1e-3
    assert resumed["steps"] == pytest.approx(reference["steps"], rel=0.05)


def test_sigkill_at_a_random_moment_then_resume(reference: dict, tmp_path: Path) -> None:
    seed = random.randrange(10**6)
    rows = random.Random(seed).randint(15, reference["steps"] - 100)
    out = tmp_path / "run"
    proc = start(out)
    wait_for_rows(out, rows, proc)
    proc.kill()
    proc.wait()
    assert summary(out)["status"] == "running", f"seed {seed}"   # killed: no chance to write
    plotted = granflow("plot", out)                # figures from what the killed run wrote
    assert plotted.returncode == 0 and (out / "plots" / "free_surface.png").is_file()
    done = granflow("resume", out, "--quiet")
    assert done.returncode == 0, f"seed {seed}: {done.stderr}"
    assert_same_result(resumed := summary(out), reference)
    for key in ("stop_time_s", "runout_m", "steps", "nonlinear_iterations", "remeshes"):
        assert resumed[key] == pytest.approx(reference[key], rel=1e-12), f"seed {seed}: {key}"


def test_sigint_checkpoints_and_resumes_and_a_running_directory_is_refused(
        reference: dict, tmp_path: Path) -> None:
    out = tmp_path / "run"
    proc = start(out)
    wait_for_rows(out, 100, proc)
    second = granflow("run", *CASE, "--out", out)
    assert second.returncode == 2 and "already holds a run" in second.stderr
    forced = granflow("run", *CASE, "--out", out, "--force")
    assert forced.returncode == 2 and "in use by another granflow process" in forced.stderr
    early = granflow("resume", out)
    assert early.returncode == 2 and "in use" in early.stderr
    errors = [line for line in second.stderr.splitlines() if not line.startswith(
        "granflow: note:")]          # the case's t_end drops an output time: a note, no error
    assert len(errors) == 1 and errors[0].startswith("granflow: error:")
    proc.send_signal(signal.SIGINT)
    assert proc.wait(timeout=120) == 130
    interrupted = summary(out)
    assert interrupted["status"] == "interrupted" and (out / "checkpoint/state.npz").is_file()
    assert interrupted["steps"] < reference["steps"]
    assert final_front(out) == pytest.approx(interrupted["runout_m"], abs=1e-12)  # where it stood
    assert interrupted["final_profiles_t"] == interrupted["t_final"]
    done = granflow("resume", out, "--quiet")
    assert done.returncode == 0, done.stderr
    assert_same_result(resumed := summary(out), reference)
    assert final_front(out) == pytest.approx(resumed["runout_m"], abs=1e-12)   # the deposit
    again = granflow("resume", out)
    assert again.returncode == 2 and "already finished" in again.stderr
