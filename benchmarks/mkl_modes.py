"""Benchmark: what MKL's reproducible kernels cost a whole run, against the CPU's own.

Run: python benchmarks/mkl_modes.py [--cases trapezoid-rigid trapezoid-erodible
         cylinder-rigid mesh-20k] [--repeat 3] [--out benchmarks/results/mkl_modes]

Each case runs as ``granflow run`` in a new process with ``MKL_CBWR=COMPATIBLE`` (SSE2
kernels: the same results on every x86-64 CPU) and with ``MKL_CBWR=AUTO`` (this CPU's own
kernels: the same results on this machine only), alternately, REPEAT times; each process is
timed from outside (wall time from start to exit, processor time from the operating
system's account of the finished child) with the load average (1 min) before it. The
cases: the three default collapses to rest, and ``mesh-20k``, the rigid trapezoid meshed to
about 20,000 triangles (``mesh.size`` = 0.0027 m) for three steps of 0.1 ms, where
PARDISO's factorisation is most of an iteration. Prints, per case, the medians and the
ratio COMPATIBLE / AUTO of the wall and processor times (the median of the rounds' ratios)
and whether the two modes gave the same run (steps, iterations, runout), and writes
OUT/mkl_modes.json.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
from pathlib import Path

from common.process import timed_run
from common.results import report, write_json, write_markdown

CASES = {
    "trapezoid-rigid": ("trapezoid-rigid", []),
    "trapezoid-erodible": ("trapezoid-erodible", []),
    "cylinder-rigid": ("cylinder-rigid", []),
    "mesh-20k": ("trapezoid-rigid", ["mesh.size=0.0027", "time.dt=1e-4", "time.t_end=3e-4",
                                     "time.output_times=[]"]),
}
MODES = ("COMPATIBLE", "AUTO")
FIGURES = ["steps", "nonlinear_iterations", "n_triangles", "runout_m", "stop_time_s"]


def run(scenario: str, sets: list[str], mode: str, out: Path) -> dict:
    """One ``granflow run`` with MKL_CBWR = ``mode``: its times and its figures."""
    result = timed_run(scenario, sets, out, env={"MKL_CBWR": mode})
    summary = result["summary"]
    return {"wall_s": result["process_wall_time_s"], "cpu_s": result["process_cpu_time_s"],
            "load_before": result["load_before"], "loop_wall_s": summary.get("wall_time_s")
            } | {k: summary.get(k) for k in FIGURES}


def measure(name: str, repeat: int, out: Path) -> dict:
    scenario, sets = CASES[name]
    runs: dict[str, list[dict]] = {mode: [] for mode in MODES}
    for k in range(repeat):
        for mode in MODES:
            runs[mode].append(run(scenario, sets, mode, out / "runs" / name / f"{mode}{k}"))
            report(f"{name} {mode} {k}", runs[mode][-1])
    ratio = {key: statistics.median(c[key] / a[key] for c, a in
                                    zip(runs["COMPATIBLE"], runs["AUTO"], strict=True))
             for key in ("wall_s", "cpu_s")}
    return {"scenario": scenario, "overrides": sets, "runs": runs,
            "median": {m: {k: statistics.median(r[k] for r in rows) for k in
                           ("wall_s", "cpu_s", "load_before")} for m, rows in runs.items()},
            "ratio_compatible_to_auto": ratio,
            "same_run": all(runs["COMPATIBLE"][0][k] == runs["AUTO"][0][k] for k in FIGURES)}


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/mkl_modes"))
    args = parser.parse_args(argv)
    results: dict = {"machine": {"cpu": platform.processor() or platform.machine(),
                                 "cores": os.cpu_count()}}
    lines = ["| case | wall time (s), COMPATIBLE / AUTO | ratio | processor time (s) | ratio "
             "| load (1 min) | the same run |", "|---|---|---|---|---|---|---|"]
    for name in args.cases:
        r = results[name] = measure(name, args.repeat, args.out)
        write_json(args.out / "mkl_modes.json", results)
        c, a = r["median"]["COMPATIBLE"], r["median"]["AUTO"]
        lines.append(f"| {name} | {c['wall_s']:.1f} / {a['wall_s']:.1f} | "
                     f"{r['ratio_compatible_to_auto']['wall_s']:.3f} | "
                     f"{c['cpu_s']:.1f} / {a['cpu_s']:.1f} | "
                     f"{r['ratio_compatible_to_auto']['cpu_s']:.3f} | "
                     f"{c['load_before']:.1f} | {'yes' if r['same_run'] else 'no'} |")
    write_markdown(args.out / "mkl_modes.md", lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
