"""The 3D column's walls held strongly (``boundary.non_penetration = "strong"``): the
same flow as with the penalty (2.7), and the refusals; and the iterative solve measured in
benchmarks/three_d_krylov.py (GMRes, BDDC on the velocity), which needs them: on a flowing
coarse column it reaches the direct solution, on one rank and on two alike.

The coarse column of tests/verification/test_mpi.py (half a 10 cm channel, mesh.size =
0.04, to t = 0.02 s). The penalty 1e12 leaves a normal velocity of about the normal
traction over 1e12 (1e-9 m/s), far below the nonlinear tolerance 1e-7: held strongly,
the run takes the same steps and its runout is the same to that tolerance (the front's
1.2 mm displacement to 1e-4: the tolerance holds each step's velocity in L2, a front's
point moves by their sum)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from granflow.app.api import run
from granflow.config import ConfigError, load_config

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mpi_runs import MPIEXEC, granflow_on_ranks, needs_mpi  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
COLUMN = ["geometry.dimension=3", "mesh.size=0.04", "time.t_end=0.02",
          "time.output_times=[0.01]", "boundary.channel_width=0.1"]
STRONG = [*COLUMN, "boundary.non_penetration=strong"]
TOL = 1e-7      # numerics.tol of the column: the nonlinear iteration's
L0 = 0.2        # the rectangle's length: the front starts there


@pytest.mark.slow
def test_walls_held_strongly_flow_as_the_penalty_lets_them(tmp_path: Path) -> None:
    penalty = run("rectangle-rigid", COLUMN, out=tmp_path / "penalty", progress=False).summary
    strong = run("rectangle-rigid", STRONG, out=tmp_path / "strong", progress=False).summary
    assert penalty.status == strong.status == "completed"
    assert strong.steps == penalty.steps
    assert strong.runout_m == pytest.approx(penalty.runout_m, rel=TOL)
    moved = penalty.runout_m - L0                            # 1.2 mm
    assert moved > 1e-3
    assert strong.runout_m - L0 == pytest.approx(moved, rel=1e-4)   # measured: 8e-6
    assert strong.extra["n_dofs"] == penalty.extra["n_dofs"]   # the same space, fewer free


@pytest.mark.slow
@needs_mpi
def test_walls_held_strongly_on_two_ranks_as_on_one(tmp_path: Path) -> None:
    """``mpiexec -n 2 granflow run``: the distributed solve holds the same components (the
    ranks update their spaces together), the same steps and runout as one process."""
    granflow_on_ranks("rectangle-rigid", STRONG, tmp_path / "two")
    two = json.loads((tmp_path / "two" / "summary.json").read_text())
    one = run("rectangle-rigid", STRONG, out=tmp_path / "one", progress=False).summary
    assert two["status"] == one.status == "completed"
    assert two["steps"] == one.steps
    assert two["runout_m"] == pytest.approx(one.runout_m, rel=TOL)


@pytest.mark.parametrize("kind, sets, words", [
    ("rectangle-rigid", ["boundary.non_penetration=strong"], "geometry.dimension = 3"),
    ("rectangle-rigid", [*STRONG, "boundary.normal_load=reaction"], "has no penalty"),
    ("plug-flow", ["geometry.dimension=3", "boundary.non_penetration=strong"], "no walls"),
    ("slab", ["boundary.non_penetration=strong"], "two dimensions"),
])
def test_what_the_strong_walls_refuse(kind: str, sets: list[str], words: str) -> None:
    with pytest.raises(ConfigError, match=words):
        load_config(kind, sets)


def _krylov(tmp_path: Path, ranks: int) -> dict:
    """benchmarks/three_d_krylov.py on the flowing coarse column, eps = 1e-2."""
    command = [sys.executable, str(ROOT / "benchmarks" / "three_d_krylov.py"), "--eps", "1e-2",
               "--schur", "cahouet-chabard", "--out", str(tmp_path)]
    if ranks > 1:
        command = [str(MPIEXEC), "-n", str(ranks), *command]
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    done = subprocess.run(command, capture_output=True, text=True, timeout=600, env=env,
                          cwd=ROOT, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(next(line for line in done.stdout.splitlines() if line.startswith("{")))


def test_the_iterative_solve_reaches_the_direct_one(tmp_path: Path) -> None:
    row = _krylov(tmp_path, 1)
    assert row["steps_to"]["1e-08"] is not None              # GMRes converged
    assert row["relative_error"] < 1e-6


@needs_mpi
def test_the_iterative_solve_on_two_ranks_is_the_serial_one(tmp_path: Path) -> None:
    """BDDC and GMRes distributed by NGSolve: the same steps, the same distance to the
    direct solution to GMRes's tolerance."""
    one, two = _krylov(tmp_path / "one", 1), _krylov(tmp_path / "two", 2)
    assert two["ranks"] == 2 and two["unknowns"] == one["unknowns"]
    assert abs(two["gmres_steps"] - one["gmres_steps"]) <= 1
    assert two["relative_error"] == pytest.approx(one["relative_error"], rel=1e-3, abs=1e-8)
