"""Benchmark: the augmented Lagrangian method (ALG2) against the regularised law
on the plug flow (paper section 4), side by side in one run.

Run: python benchmarks/augmented_lagrangian.py [--dz 0.125] [--dt 3.12e-3]
         [--out benchmarks/results/augmented_lagrangian]

Cells (the 2-cell strip of `granflow verify`, fixed mesh, t = 0.2 s, tol = 1e-7):
- regularised (2.13), Picard (3.2), eps = 1e-2 and 1e-6; Newton, eps = 1e-6;
- augmented Lagrangian, r = 20 x viscosity (auto);
relative L2 error against the 1D reference, nonlinear iterations and wall time of each.
Then the choice of r: iterations of the first step (dZ = 0.25, dt = 1.25e-2) for r = 0.2,
2, 20 and 200 x viscosity. Writes OUT/augmented_lagrangian.json and .md.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from common.results import report, write_results

from granflow.config import load_config
from granflow.scenarios.plug_flow import build_plug_flow

METHODS = {
    "regularised, Picard, eps = 1e-2": ["numerics.linearization=picard", "numerics.eps=1e-2"],
    "regularised, Picard, eps = 1e-6": ["numerics.linearization=picard", "numerics.eps=1e-6"],
    "regularised, Newton, eps = 1e-6": ["numerics.linearization=newton", "numerics.eps=1e-6"],
    "augmented Lagrangian, r = 20 eta": ["numerics.method=augmented-lagrangian"],
}


def cell(dz: float, dt: float, extra: list[str], t_end: float = 0.2) -> dict:
    overrides = [f"time.dt={dt!r}", f"mesh.size={dz!r}", f"geometry.length={2 * dz!r}",
                 "mesh.cells_x=2", "time.output_times=[]", "numerics.mesh_velocity=fixed",
                 f"time.t_end={t_end!r}", *extra]
    problem = build_plug_flow(load_config("plug-flow", overrides))
    start = time.perf_counter()
    result = problem.simulation.run()
    wall = time.perf_counter() - start
    return {"status": result.status, "error": problem.velocity_error(result.t_final),
            "iterations": result.nonlinear_iterations, "steps": result.steps,
            "wall_time_s": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--dz", type=float, default=0.125)
    parser.add_argument("--dt", type=float, default=3.12e-3)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/augmented_lagrangian"))
    args = parser.parse_args()
    rows = []
    for name, extra in METHODS.items():
        rows.append({"method": name, **cell(args.dz, args.dt, extra)})
        report("", rows[-1])
    viscosity = load_config("plug-flow").material.viscosity
    choice = []
    for factor in (0.2, 2.0, 20.0, 200.0):
        r = factor * viscosity
        result = cell(0.25, 1.25e-2, ["numerics.method=augmented-lagrangian",
                                      f"numerics.al_r={r!r}", "numerics.max_iterations=5000"],
                      t_end=1.25e-2)
        choice.append({"r_over_viscosity": factor, **result})
        report("", choice[-1])
    lines = [f"Plug flow, dZ = {args.dz}, dt = {args.dt}, t = 0.2 s, tol = 1e-7:", "",
             "| method | relative L2 error | nonlinear iterations | wall (s) |",
             "|---|---|---|---|"]
    lines += [f"| {r['method']} | {r['error']:.3e} | {r['iterations']} | {r['wall_time_s']:.1f} |"
              for r in rows]
    lines += ["", "Choice of r (first step, dZ = 0.25, dt = 1.25e-2):", "",
              "| r / viscosity | iterations | status |", "|---|---|---|"]
    lines += [f"| {c['r_over_viscosity']:g} | {c['iterations']} | {c['status']} |"
              for c in choice]
    write_results(args.out, "augmented_lagrangian", {"cells": rows, "r_choice": choice}, lines,
                  show=True)


if __name__ == "__main__":
    main()
