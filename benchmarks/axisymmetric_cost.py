"""Benchmark: the cost of an axisymmetric collapse against the plane-strain collapse of the
same section on the same mesh size, side by side in one invocation.

Run: python benchmarks/axisymmetric_cost.py [--repeat 3] [--size 0.014]
         [--out benchmarks/results/axisymmetric_cost]

P is the plane-strain rectangle of the cylinder's section (width = r0 = 10 cm, h0 = 14 cm,
rectangle-rigid with geometry.width = 0.1), A the cylinder (cylinder-rigid); both with the
fixed point (3.2) ("picard": the primal-dual correction is plane strain only), the same
tolerances and steps, run to rest, alternately (P, A, P, A, ...). The two flows differ
(a cylinder spreads in r and stops sooner), so beside the whole-run wall-time ratio A/P the
table gives the wall time per nonlinear iteration, which compares the work of one
iteration on the two forms. The runs go to OUT/runs/; writes OUT/cost.json and prints a table.
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from common.results import report, write_json
from common.runs import run_summary

CASES = {"P": ("rectangle-rigid", ["geometry.width=0.1", "numerics.linearization=picard"]),
         "A": ("cylinder-rigid", [])}
COMMON = ["time.t_end=3.0", "time.output_times=[0.2]"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--size", type=float, default=0.014, help="mesh.size of both (m)")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/axisymmetric_cost"))
    args = parser.parse_args()
    runs: dict[str, list[dict]] = {label: [] for label in CASES}
    for k in range(args.repeat):
        for label, (scenario, extra) in CASES.items():
            summary = run_summary(scenario, [*extra, *COMMON, f"mesh.size={args.size!r}"],
                                  args.out / "runs" / f"{label}{k}")
            runs[label].append(summary)
            report(f"{label} {k}", {x: summary[x] for x in (
                "status", "steps", "nonlinear_iterations", "wall_time_s", "stop_time_s",
                "runout_m", "n_triangles")})
    med = {label: statistics.median(r["wall_time_s"] for r in rows)
           for label, rows in runs.items()}
    per_it = {label: statistics.median(r["wall_time_s"] / r["nonlinear_iterations"]
                                       for r in rows) for label, rows in runs.items()}
    result = {"mesh_size_m": args.size, "repeat": args.repeat, "runs": runs,
              "wall_time_median_s": med, "wall_time_per_iteration_median_s": per_it,
              "ratio_A_over_P": med["A"] / med["P"],
              "ratio_per_iteration_A_over_P": per_it["A"] / per_it["P"]}
    write_json(args.out / "cost.json", result)
    print(f"| run | triangles | steps | iterations | wall time (s, median of {args.repeat}) "
          "| per iteration (ms) |\n|---|---|---|---|---|---|")
    for label, rows in runs.items():
        r = rows[0]
        print(f"| {label} {CASES[label][0]} | {r['n_triangles']} | {r['steps']} | "
              f"{r['nonlinear_iterations']} | {med[label]:.1f} | {1e3 * per_it[label]:.2f} |")
    print(f"A/P whole run: {result['ratio_A_over_P']:.2f}; per iteration: "
          f"{result['ratio_per_iteration_A_over_P']:.2f}")


if __name__ == "__main__":
    main()
