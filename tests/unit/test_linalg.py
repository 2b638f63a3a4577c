"""The sparse LU of the momentum system (3.2) solves it to round-off (fem/linalg.py)."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import ngsolve as ngs
import pytest

from granflow.config import load_config
from granflow.fem import linalg
from granflow.fem.linalg import ReusableLU, direct_solver
from granflow.runner import build_problem


@pytest.mark.parametrize("solver", ["pardiso", "pardiso-metis", "umfpack"])
def test_column_system_solved_to_round_off(solver: str,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """Relative residual of (3.2) below 1e-12 after a few Picard iterations of the first
    step, both solvers agreeing to 1e-10, also after a numeric refactorisation. The matrix
    carries the 1e12 wall penalty beside viscosities of 1 to 1e9 Pa s: PARDISO without its
    default iterative refinement must still be exact here."""
    if solver.startswith("pardiso") and direct_solver("auto") != "pardiso":
        pytest.skip("Intel MKL not installed")
    if solver == "pardiso-metis":      # the ordering of large systems, here at 1,606 unknowns
        monkeypatch.setattr(linalg, "METIS_FROM_UNKNOWNS", 0)
        solver = "pardiso"
    problem = build_problem(load_config("trapezoid-rigid"))
    flow = problem.solver
    flow.dt.Set(1e-3)
    system = flow.nonlinear.picard_system
    system.prepare()
    for _ in range(3):
        system.iterate(flow.solution.vec)
    matrix, rhs = system.assemble(), system.f.vec
    lu = ReusableLU(system.a, flow.space.FreeDofs(), solver)
    reference = ngs.BaseVector(len(rhs), False)
    reference.data = matrix.Inverse(flow.space.FreeDofs(), inverse="umfpack") * rhs
    for _ in range(2):                    # the analysis, then a numeric refactorisation
        lu.update()
        x, residual = rhs.CreateVector(), rhs.CreateVector()
        lu.solve(rhs, x)
        residual.data = rhs - matrix * x
        assert ngs.Norm(residual) < 1e-12 * ngs.Norm(rhs)
        residual.data = x - reference
        assert ngs.Norm(residual) < 1e-10 * ngs.Norm(reference)
        system.iterate(flow.solution.vec)
        matrix = system.assemble()
        reference.data = matrix.Inverse(flow.space.FreeDofs(), inverse="umfpack") * rhs


def test_mkl_runs_the_cpus_kernels_unless_asked_for_reproducible_ones() -> None:
    """PARDISO runs MKL's own choice of kernels for the CPU (the fastest: the reproducible
    SSE2 ones cost 47 % more processor time on a 20,000-triangle mesh, docs/performance.md,
    Reproducibility), and ``MKL_CBWR=COMPATIBLE``, the documented switch, gives the
    kernels that round alike on every x86-64 CPU. Checked in fresh processes, as a user
    starts one."""
    if direct_solver("auto") != "pardiso":
        pytest.skip("Intel MKL not installed")
    probe = textwrap.dedent("""
        import ctypes, pathlib
        import granflow
        from granflow.fem.linalg import pardiso_available
        assert pardiso_available()
        loaded = pathlib.Path("/proc/self/maps").read_text().split()
        runtime = next(p for p in loaded if pathlib.Path(p).name.startswith("libmkl_rt.so"))
        print(ctypes.CDLL(runtime).MKL_CBWR_Get(1))   # MKL_CBWR_BRANCH (mkl_service.h)
    """)
    if not Path("/proc/self/maps").exists():
        pytest.skip("the loaded libraries are listed in /proc on Linux only")
    unset = {k: v for k, v in os.environ.items() if k != "MKL_CBWR"}
    branches = {}
    for mode, env in (("unset", unset), ("COMPATIBLE", {**unset, "MKL_CBWR": "COMPATIBLE"})):
        done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                              env=env, timeout=120)
        assert done.returncode == 0, done.stderr
        branches[mode] = done.stdout.split()[-1]
    assert branches["COMPATIBLE"] == "3"              # MKL_CBWR_COMPATIBLE
    assert branches["unset"] != "3"                   # MKL's own, the CPU's kernels
