"""Benchmark: how the processor time of one solve of (3.2) in 3D grows with the problem's
size, for the direct solve and for granflow's scaled fieldsplit solve (selfp and LSC).

Run: python benchmarks/three_d_fieldsplit_cost.py [--size 0.04 0.02 0.014 0.01]
         [--state rest flowing front] [--rounds 2] [--solvers umfpack lsc-gamg-flexible]
         [--out benchmarks/results/three_d_fieldsplit]
     python benchmarks/three_d_fieldsplit_cost.py --table [--out ...]

Needs petsc4py and ngspetsc (one line and exit code 2 without them). The systems are
``three_d_fieldsplit.py``'s (the column's first Picard system at rest, flowing, front;
eps = 1e-6, dt = 1e-4 s). Each size runs in its own process (so that its peak resident
memory is its own), one after the other; in it, per state, the system is assembled once and
solved ``--rounds`` times by each solver, the last round counted: UMFPACK and PARDISO
(NGSolve's ``Inverse``; the factorisation and the solve), and ``FieldsplitSolve`` with the
variants ``selfp-gamg-flexible`` and ``lsc-gamg-flexible`` (the hand-over to PETSc, the
set-up and the solve). Recorded: processor seconds, FGMRes steps, the distance to UMFPACK,
the resident memory the factor or the fieldsplit solve added (first round), the process's
peak. Writes cost_<state>_h<size>.json; ``--table`` fits the time per solve as k N^a by least
squares in log-log over the sizes (``common.fieldsplit_cost``), prints the Markdown table and
writes cost.json and cost.md: the exponents and the size where each fieldsplit variant
becomes as cheap as the cheaper direct solve, on one process and on P ranks. With
``--solvers`` fewer than all, the records are check_<state>_h<size>.json, left out of the
fits, and the table compares them with the fits' times.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

from common.fieldsplit_cost import report

SOLVERS = ("umfpack", "pardiso", "selfp-gamg-flexible", "lsc-gamg-flexible")


def resident_mb() -> float:
    """This process's resident memory now (MB)."""
    pages = int(Path("/proc/self/statm").read_text().split()[1])
    return pages * resource.getpagesize() / 2**20


def direct(matrix, space, rhs, kind: str) -> tuple[dict, object]:
    """NGSolve's direct solve ``kind``: processor seconds, memory added, the solution."""
    before = resident_mb()
    c0 = time.process_time()
    inverse = matrix.Inverse(space.FreeDofs(), inverse=kind)
    out = rhs.CreateVector()
    out.data = inverse * rhs
    cpu = time.process_time() - c0
    record = {"cpu_s": cpu, "added_mb": resident_mb() - before, "steps": 0}
    del inverse
    return record, out


def iterative(form, space, rhs, variant: str) -> tuple[dict, object]:
    """granflow's scaled fieldsplit solve ``variant``: processor seconds (hand-over,
    set-up, solve), FGMRes steps, memory added, the solution."""
    from granflow.fem.fieldsplit import FieldsplitSolve, LinearSolveFailed

    before = resident_mb()
    c0 = time.process_time()
    solve = FieldsplitSolve(form, space.FreeDofs(), variant=variant)
    solve.update()
    solve.ksp.setUp()
    c1 = time.process_time()
    out = rhs.CreateVector()
    try:
        solve.solve(rhs, out)
        converged = True
    except LinearSolveFailed:
        converged = False
    c2 = time.process_time()
    record = {"cpu_s": c2 - c0, "setup_s": c1 - c0, "solve_s": c2 - c1,
              "steps": solve.steps, "converged": converged,
              "added_mb": resident_mb() - before}
    solve.reset()
    return record, out


def one_size(size: float, states: list[str], rounds: int, out: Path,
             solvers: tuple[str, ...] = SOLVERS) -> None:
    """Every state's record at one mesh size (this process); with fewer ``solvers`` than
    all, an out-of-sample check of the fits: check_<state>_h<size>.json, not fitted."""
    import ngsolve as ngs
    from three_d_fieldsplit import picard_system

    ngs.SetNumThreads(1)
    for state in states:
        solver, matrix, rhs = picard_system(state, size, 1e-6, 1e-4, None)
        form = solver.nonlinear.picard_system.a
        space = solver.space
        rows: dict[str, list[dict]] = {name: [] for name in solvers}
        reference = None
        for _ in range(rounds):
            for name in solvers:
                if name in ("umfpack", "pardiso"):
                    record, x = direct(matrix, space, rhs, name)
                else:
                    record, x = iterative(form, space, rhs, name)
                if reference is None:
                    reference = x
                gap = rhs.CreateVector()
                gap.data = x - reference
                record["relative_difference"] = ngs.Norm(gap) / ngs.Norm(reference)
                rows[name].append(record)
        result = {"state": state, "size": size, "eps": 1e-6, "dt": 1e-4,
                  "free_unknowns": int(sum(space.FreeDofs())), "unknowns": space.ndof,
                  "rounds": rows,
                  "counted": {name: runs[-1] for name, runs in rows.items()},
                  "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                  "load_average": os.getloadavg()}
        print(json.dumps({"state": state, "size": size, "n": result["free_unknowns"],
                          **{k: (round(v["cpu_s"], 3), v["steps"])
                             for k, v in result["counted"].items()}}), flush=True)
        kind = "cost" if solvers == SOLVERS else "check"
        (out / f"{kind}_{state}_h{size:g}.json").write_text(
            json.dumps(result, indent=1) + "\n", encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, nargs="+", default=[0.04, 0.02, 0.014, 0.01])
    parser.add_argument("--state", nargs="+", choices=["rest", "flowing", "front"],
                        default=["rest", "flowing", "front"])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/three_d_fieldsplit"))
    parser.add_argument("--table", action="store_true",
                        help="fit the records in --out, print the table, write cost.json/md")
    parser.add_argument("--solvers", nargs="+", choices=SOLVERS, default=list(SOLVERS),
                        help="fewer than all: records check_*.json, left out of the fits")
    parser.add_argument("--one-size", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.table:
        text, data = report(args.out)
        print(text)
        (args.out / "cost.md").write_text(text + "\n", encoding="utf-8")
        (args.out / "cost.json").write_text(json.dumps(data, indent=1) + "\n",
                                            encoding="utf-8")
        return 0
    try:
        import ngsPETSc  # noqa: F401
        import petsc4py  # noqa: F401
    except ImportError:
        print("three_d_fieldsplit_cost.py needs petsc4py and ngspetsc "
              "(pip install petsc petsc4py ngspetsc); they are not installed here",
              file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    if args.one_size:
        one_size(args.size[0], args.state, args.rounds, args.out,
                 tuple(s for s in SOLVERS if s in args.solvers))
        return 0
    for size in args.size:
        code = subprocess.call([sys.executable, __file__, "--one-size", "--size", str(size),
                                "--rounds", str(args.rounds), "--out", str(args.out),
                                "--state", *args.state, "--solvers", *args.solvers])
        if code:
            return code
    return main(["--table", "--out", str(args.out)])


if __name__ == "__main__":
    sys.exit(main())
