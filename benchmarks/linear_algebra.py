"""Benchmark: the sparse LU of one Picard iteration (3.2) of the default collapse, by solver.

Run: python benchmarks/linear_algebra.py [--t 0.3] [--repeat 30]
         [--out benchmarks/results/linear_algebra]

Runs `trapezoid-rigid` to t (default 0.3 s, mid-flow), takes the matrix of the last
iteration and times, side by side in one process, the median of --repeat calls of:
assembling it (the iterate's part, the constant part and the primal-dual correction);
NGSolve's UMFPACK numeric refactorisation (what a run does at each iteration), a fresh
UMFPACK factorisation (after a remesh) and a back-substitution; the same with PARDISO when
Intel MKL is installed (`pip install -e ".[fast]"`); SciPy's SuperLU; and UMFPACK called
directly through CVXOPT when it is installed (numeric phase only, no NGSolve wrapper). It
prints a table and writes JSON: what one iteration costs and which solver is fastest here.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import timeit
from collections.abc import Callable
from pathlib import Path

import ngsolve as ngs
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from common.results import write_json

from granflow.config import load_config
from granflow.fem.linalg import pardiso_available
from granflow.runner import build_problem


def median_ms(call: Callable[[], object], repeat: int) -> float:
    return 1e3 * statistics.median(timeit.repeat(call, number=1, repeat=repeat))


def timings(t: float, repeat: int) -> dict:
    config = load_config("trapezoid-rigid", [f"time.t_end={t}", "output.progress=false"])
    problem = build_problem(config)
    problem.simulation.run()
    system = problem.solver.nonlinear.picard_system
    freedofs = problem.solver.space.FreeDofs()
    out = system.f.vec.CreateVector()
    result: dict = {"t": t, "unknowns": int(freedofs.NumSet()),
                    "triangles": problem.mesh.ne, "ms": {}}
    ms = result["ms"]
    ms["assemble iterate part"] = median_ms(system.a.Assemble, repeat)
    ms["assemble whole matrix (+ correction)"] = median_ms(lambda: system.assemble(True), repeat)
    system.assemble(True)
    rows, cols, values = system.a.mat.COO()
    matrix = sp.csc_matrix((np.asarray(values), (np.asarray(rows), np.asarray(cols))),
                           shape=(system.a.mat.height,) * 2)
    result["nonzeros"] = matrix.nnz
    for solver in ["umfpack", *(["pardiso"] if pardiso_available() else [])]:
        inverse = system.a.mat.Inverse(freedofs, inverse=solver)
        ms[f"{solver} refactorise (Update)"] = median_ms(inverse.Update, repeat)
        ms[f"{solver} fresh factorisation"] = median_ms(
            lambda s=solver: system.a.mat.Inverse(freedofs, inverse=s), max(repeat // 3, 3))

        def back_substitute(inverse: ngs.BaseMatrix = inverse) -> None:
            out.data = inverse * system.f.vec

        ms[f"{solver} back-substitution"] = median_ms(back_substitute, repeat)
    lu = spla.splu(matrix, permc_spec="COLAMD")
    result["superlu_factor_nonzeros"] = int(lu.L.nnz + lu.U.nnz)
    ms["superlu (scipy) factorisation"] = median_ms(
        lambda: spla.splu(matrix, permc_spec="COLAMD"), max(repeat // 3, 3))
    ms["superlu back-substitution"] = median_ms(lambda: lu.solve(np.ones(matrix.shape[0])),
                                                repeat)
    try:
        from cvxopt import spmatrix, umfpack
    except ImportError:
        result["cvxopt"] = "not installed (pip install cvxopt)"
    else:
        coo = matrix.tocoo()
        a = spmatrix(coo.data.tolist(), coo.row.tolist(), coo.col.tolist(), matrix.shape)
        symbolic = umfpack.symbolic(a)
        ms["umfpack (cvxopt) numeric phase"] = median_ms(lambda: umfpack.numeric(a, symbolic),
                                                         repeat)
    return result


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--t", type=float, default=0.3)
    parser.add_argument("--repeat", type=int, default=30)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/linear_algebra"))
    args = parser.parse_args(argv)
    ngs.SetNumThreads(1)
    result = timings(args.t, args.repeat)
    write_json(args.out / "lu.json", result)
    print(f"{result['unknowns']} unknowns, {result['triangles']} triangles, "
          f"{result['nonzeros']} nonzeros at t = {result['t']} s")
    for name, value in result["ms"].items():
        print(f"  {name:40s} {value:8.2f} ms")


if __name__ == "__main__":
    main(sys.argv[1:])
