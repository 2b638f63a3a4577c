"""Benchmark: how small numerics.tol can be: the iterations per step of the fixed-point
iteration (3.2) as the tolerance falls to round-off, on a coarse column.

Run: python benchmarks/tolerance_floor.py [--tols 3e-5 1e-8 1e-10 1e-12 1e-14]
         [--t-end 0.01] [--out benchmarks/results/tolerance_floor]

A 10 cm square column on a 2 cm mesh (about 50 triangles) runs to T_END at each tolerance
(rules off: the smallest tolerances are below what granflow accepts); per tolerance: the
accepted steps, the nonlinear iterations per step, the attempts that reached
numerics.max_iterations unconverged (rejected and retried smaller: ``not_converged``), the
wall time. Backs ``TOL_FLOOR`` (granflow/config/cost.py): above it every step converges,
below it steps end at max_iterations. Writes OUT/tolerance_floor.json.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from common.results import write_json

from granflow.config import load_config
from granflow.runner import build_problem

CASE = ["geometry.width=0.1", "geometry.height=0.1", "mesh.size=0.02", "time.output_times=[]",
        "output.progress=false"]


def run(tol: float, t_end: float) -> dict:
    config = load_config("rectangle-rigid", [*CASE, f"time.t_end={t_end!r}"])
    # below the floor the configuration is refused: set the tolerance past the rules
    config = config.model_copy(update={"numerics": config.numerics.model_copy(
        update={"tol": tol})})
    problem = build_problem(config)
    start = time.perf_counter()
    result = problem.simulation.run()
    steps = max(1, result.steps)
    return {"tol": tol, "status": result.status, "t_final": result.t_final,
            "steps": result.steps, "iterations_per_step": result.nonlinear_iterations / steps,
            "rejected_steps": result.rejected_steps,
            "not_converged": result.rejections.get("not_converged", 0),
            "n_triangles": problem.mesh.ne, "wall_s": time.perf_counter() - start}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tols", type=float, nargs="+",
                        default=[3e-5, 1e-8, 1e-10, 1e-12, 1e-14])
    parser.add_argument("--t-end", type=float, default=0.01)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/tolerance_floor"))
    args = parser.parse_args()
    rows = []
    for tol in args.tols:
        rows.append(row := run(tol, args.t_end))
        print(f"tol {tol:8.1e}: {row['status']:9s} t = {row['t_final']:.4g} s, "
              f"{row['steps']} steps, {row['iterations_per_step']:6.1f} iterations a step, "
              f"{row['not_converged']} attempts unconverged, {row['wall_s']:6.1f} s")
    write_json(args.out / "tolerance_floor.json", {"case": CASE, "t_end": args.t_end,
                                                    "rows": rows}, end="\n")


if __name__ == "__main__":
    main()
