"""Rung 11: one and two MPI ranks agree. The 3D layer of the plug flow (two coarse steps)
run by ``mpiexec -n 2`` (NGSolve distributes a copy of rank 0's mesh for the flow's solve,
the direct solver gathers on rank 0) against the same run in this process, to the nonlinear tolerance.

Needs the MPI extra (``pip install -e ".[mpi]"``: mpi4py and MPICH from the package index);
skipped without it, except in CI, which installs it."""

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from mpi_layer_3d import run  # noqa: E402

MPIEXEC = Path(sys.executable).parent / "mpiexec"
HAVE_MPI = importlib.util.find_spec("mpi4py") is not None and MPIEXEC.exists()
TOL = 1e-7      # numerics.tol of the plug-flow scenario: the nonlinear iteration's


@pytest.mark.skipif(not HAVE_MPI and not os.environ.get("CI"),
                    reason='needs the MPI extra: pip install -e ".[mpi]"')
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
