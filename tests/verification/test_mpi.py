"""Rung 11: one and two MPI ranks agree. The 3D layer of the plug flow (two coarse steps)
run by ``mpiexec -n 2`` (NGSolve distributes a copy of rank 0's mesh for the solve, the
direct solver gathers on rank 0) against the same run in this process, to the nonlinear
tolerance.

Needs the MPI extra (``pip install -e ".[mpi]"``: mpi4py and MPICH from the package index);
skipped without it, except in CI, which installs it."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from mpi_layer_3d import run  # noqa: E402
from mpi_runs import HAVE_MPI, MPIEXEC, granflow_on_ranks, needs_mpi  # noqa: E402

TOL = 1e-7      # numerics.tol of the plug-flow scenario: the nonlinear iteration's


@needs_mpi
def test_two_ranks_agree_with_one() -> None:
    assert HAVE_MPI, 'CI installs the MPI extra: pip install -e ".[mpi]"'
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    done = subprocess.run([str(MPIEXEC), "-n", "2", sys.executable,
                           str(HERE / "mpi_layer_3d.py")], capture_output=True, text=True,
                          timeout=600, env=env, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    lines = [line for line in done.stdout.splitlines() if line.startswith("{")]
    assert len(lines) == 1, done.stdout          # rank 0 alone reports
    two, one = json.loads(lines[0]), run()
    assert (two["ranks"], one["ranks"]) == (2, 1)
    assert two["status"] == one["status"] == "completed"
    assert two["steps"] == one["steps"] and two["unknowns"] == one["unknowns"]
    for key in ("error", "kinetic_energy", "speed_l2"):
        assert two[key] == pytest.approx(one[key], rel=TOL), key


COLUMN = ["geometry.dimension=3", "mesh.size=0.04", "time.t_end=0.02",
          "time.output_times=[0.01]", "boundary.channel_width=0.1"]


@needs_mpi
def test_the_3d_column_on_two_ranks_is_the_serial_one(tmp_path: Path) -> None:
    """``mpiexec -n 2 granflow run`` of a coarse 3D column: the same steps and runout as
    one process (to the nonlinear tolerance), its outputs written once."""
    from granflow.app.api import run as run_case

    done = granflow_on_ranks("rectangle-rigid", COLUMN, tmp_path / "two")
    assert done.stdout.count("run directory") == 1, done.stdout      # rank 0 alone reports
    one = run_case("rectangle-rigid", COLUMN, out=tmp_path / "one", progress=False)
    two = json.loads((tmp_path / "two" / "summary.json").read_text())
    assert two["status"] == one.summary.status == "completed"
    assert two["steps"] == one.summary.steps
    assert two["runout_m"] == pytest.approx(one.summary.runout_m, rel=TOL)
    rows = [(tmp_path / name / "diagnostics.csv").read_text().count("\n")
            for name in ("one", "two")]
    assert rows[0] == rows[1]                                        # written once
