"""What the MPI tests share: whether the MPI extra is installed, the skip marker that says
how to install it (CI installs it, so CI never skips), and ``granflow run`` under
``mpiexec``."""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

MPIEXEC = Path(sys.executable).parent / "mpiexec"
HAVE_MPI = importlib.util.find_spec("mpi4py") is not None and MPIEXEC.exists()
INSTALL = 'needs the MPI extra: pip install -e ".[mpi]"'
needs_mpi = pytest.mark.skipif(not HAVE_MPI and not os.environ.get("CI"), reason=INSTALL)


def granflow_on_ranks(scenario: str, sets: list[str], out: Path,
                      ranks: int = 2) -> subprocess.CompletedProcess[str]:
    """``mpiexec -n RANKS granflow run SCENARIO --set ... --out OUT --quiet``, one thread a
    rank; asserts it exited cleanly."""
    assert HAVE_MPI, f"CI installs the MPI extra: {INSTALL}"
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
    done = subprocess.run([str(MPIEXEC), "-n", str(ranks), str(MPIEXEC.parent / "granflow"),
                           "run", scenario, *(a for key in sets for a in ("--set", key)),
                           "--out", str(out), "--quiet"], capture_output=True, text=True,
                          timeout=600, env=env, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    return done
