"""Benchmark: the primal-dual iteration (fem/primal_dual.py) against the plain
fixed point (3.2), both on granflow's default fast path otherwise, back to back.

Run: python benchmarks/primal_dual.py [--cases trapezoid rectangle tall plug-flow slope10]
         [--repeat N] [--out benchmarks/results/primal_dual]

For each case (the cases of benchmarks/speed.py, and slope10: the column of
benchmarks/initial_guess.py near rest on a 10 deg slope, to t = 0.5 s), B is the default with
numerics.linearization = "picard" and P the same with "primal-dual", run alternately
(B, P, B, P, ...). The JSON holds both summaries, the median wall times and their ratio,
nonlinear iterations and linear solves, stop times, runouts and the mean / max distance
between the free surfaces of B and P at every output time (the two iterations converge
to the same discrete solution, so they should differ only by the tolerance and by the
discrete events that round-off moves).
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

from common.cases import CASES
from common.results import report, write_json
from common.runs import run_summary, surfaces_m

# the column of benchmarks/initial_guess.py: near rest on a 10 deg slope, where the plain
# iteration contracts by only 0.96 per iteration
SLOPE10 = ("rectangle-rigid", ["geometry.width=0.1", "geometry.height=0.05",
                               "geometry.slope_deg=10.0", "boundary.normal_load=reaction",
                               "mesh.cells_across=8", "time.output_times=[0.3,0.45]",
                               "numerics.initial_guess=auto", "time.t_end=0.5"], [])
ALL_CASES = {**CASES, "slope10": SLOPE10}
VARIANTS = {"B": ["numerics.linearization=picard"],
            "P": ["numerics.linearization=primal-dual"]}


def compare(name: str, repeat: int, out: Path) -> dict:
    scenario, common, _ = ALL_CASES[name]
    result: dict = {"scenario": scenario, "common_overrides": common, "variants": VARIANTS}
    walls: dict[str, list[float]] = {label: [] for label in VARIANTS}
    for k in range(repeat):
        for label, extra in VARIANTS.items():
            summary = run_summary(scenario, [*common, *extra], out / name / f"{label}{k}")
            walls[label].append(summary["wall_time_s"])
            result[label] = summary
            report(f"{name} {label} {k}", {x: summary[x] for x in (
                "status", "steps", "nonlinear_iterations", "linear_solves", "wall_time_s",
                "stop_time_s", "runout_m", "velocity_relative_error_l2")})
    b, p = result["B"], result["P"]
    medians = {label: statistics.median(v) for label, v in walls.items()}
    result |= {"wall_time_median_s": medians, "wall_times_s": walls,
               "speedup_P_over_B": medians["B"] / medians["P"],
               "iterations_ratio": b["nonlinear_iterations"] / max(p["nonlinear_iterations"], 1)}
    if b.get("runout_m") is not None and p.get("runout_m") is not None:
        result["runout_difference_m"] = p["runout_m"] - b["runout_m"]
    if b.get("stop_time_s") and p.get("stop_time_s"):
        result["stop_time_relative_difference"] = p["stop_time_s"] / b["stop_time_s"] - 1
    if scenario != "plug-flow":
        result["surfaces"] = surfaces_m(out / name / "B0", out / name / "P0")
    return result


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cases", nargs="+", choices=sorted(ALL_CASES),
                        default=["trapezoid", "rectangle", "tall", "plug-flow"])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/primal_dual"))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for name in args.cases:
        result = compare(name, args.repeat, args.out / "runs")
        write_json(args.out / f"{name}.json", result)
        print(name, "speed-up P/B", round(result["speedup_P_over_B"], 2), "iterations",
              result["B"]["nonlinear_iterations"], "/", result["P"]["nonlinear_iterations"],
              flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
