"""Benchmark: implicit Euler against BDF2 on the default collapse, and both against a
reference converged in time.

Run: python benchmarks/time_scheme.py [--out benchmarks/results/time_scheme] [--collect]

Runs `trapezoid-rigid` (each run skipped when its run directory already holds a finished
summary; --collect only compares what is there):

- ``implicit-euler``: the default (adaptive implicit Euler, dt_max 1 ms);
- ``bdf2-4ms``: ``time.scheme = "bdf2"`` with ``time.dt_max = 4e-3`` (BDF2's local error
  estimate stays near 1e-4 of the RMS speed, far under error_tol, so dt_max sets the step);
- ``reference``: the paper's algorithm (Picard (3.2), the ramp of section 3.1, tol 1e-4) at
  half its step, dt_max 5e-5, to t_end = 1.02 s (about 15 minutes).

For each run against the reference: the mean / max distance between free surfaces at the
output times, the relative difference of stop times and the difference of runouts,
checked against the accuracy targets (1 mm mean, 3 mm max, 2 %, 5 mm). Writes
OUT/time_scheme.json and prints a table.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from common.results import write_json

import granflow
from granflow.config import load_config
from granflow.io import profiles
from granflow.io.run_dir import RunDir

PAPER_HALF_STEP = ["numerics.linearization=picard", "time.adaptive=false", "time.dt_init=1e-8",
                   "time.dt_growth=1.1", "time.dt_max=5e-5", "numerics.tol=1e-4",
                   "numerics.tol_init=1e-6", "numerics.ale_extrapolation=false",
                   "numerics.initial_guess=previous", "time.stop_at_rest=false"]
RUNS = {"implicit-euler": [],
        "bdf2-4ms": ["time.scheme=bdf2", "time.dt_max=4e-3"],
        "reference": PAPER_HALF_STEP}
TARGETS = {"surface_mean_m": 1e-3, "surface_max_m": 3e-3, "stop_time_rel": 0.02,
           "runout_m": 5e-3}
KEYS = ["status", "steps", "rejected_steps", "nonlinear_iterations", "linear_solves",
        "wall_time_s", "stop_time_s", "runout_m", "linear_solver"]


def ensure_run(name: str, root: Path, collect: bool) -> dict | None:
    out = root / name
    if RunDir.is_run_dir(out):
        summary = RunDir.summary(out)
        if summary and summary.get("status") in ("completed", "stopped"):
            return summary
    if collect:
        return None
    config = load_config("trapezoid-rigid", [*RUNS[name], "output.progress=false"])
    run_dir = granflow.run(config, out=out, force=True)
    return RunDir.summary(run_dir.root)


def compare(run: Path, reference: Path, summary: dict, ref: dict) -> dict:
    surfaces = {f"{t:.3f}": {"mean_m": mean, "max_m": worst}
                for t, (mean, worst) in profiles.surface_distances(reference, run).items()}
    result = {"surfaces": surfaces,
              "surface_mean_m": max(s["mean_m"] for s in surfaces.values()),
              "surface_max_m": max(s["max_m"] for s in surfaces.values()),
              "stop_time_rel": abs(summary["stop_time_s"] / ref["stop_time_s"] - 1),
              "runout_m": abs(summary["runout_m"] - ref["runout_m"])}
    result["within_targets"] = {k: result[k] <= v for k, v in TARGETS.items()}
    return result


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/time_scheme"))
    parser.add_argument("--collect", action="store_true", help="compare existing runs only")
    args = parser.parse_args(argv)
    root = args.out / "runs"
    summaries = {name: ensure_run(name, root, args.collect) for name in RUNS}
    ref = summaries["reference"]
    result: dict = {"targets": TARGETS, "runs": {}}
    table = ["| run | steps | iterations | loop (s) | stop (s) | runout (m) | surfaces vs "
             "reference, worst mean / max (mm) | stop / runout vs reference |",
             "|---|---|---|---|---|---|---|---|"]
    for name, summary in summaries.items():
        if summary is None:
            continue
        entry = {"overrides": RUNS[name], **{k: summary.get(k) for k in KEYS}}
        if ref is not None and name != "reference":
            entry["against_reference"] = compare(root / name, root / "reference", summary, ref)
        result["runs"][name] = entry
        against = entry.get("against_reference")
        table.append(
            f"| {name} | {summary['steps']} | {summary['nonlinear_iterations']} | "
            f"{summary['wall_time_s']:.1f} | {summary['stop_time_s']:.4f} | "
            f"{summary['runout_m']:.4f} | " + (
                "-" if against is None else
                f"{1e3 * against['surface_mean_m']:.2f} / {1e3 * against['surface_max_m']:.2f}"
            ) + " | " + ("-" if against is None else
                         f"{100 * against['stop_time_rel']:.2f} % / "
                         f"{1e3 * against['runout_m']:.2f} mm") + " |")
    write_json(args.out / "time_scheme.json", result)
    print("\n".join(table))


if __name__ == "__main__":
    main(sys.argv[1:])
