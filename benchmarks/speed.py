"""Benchmark: the paper's algorithm (A) against the default fast path (B), back to back in
one invocation, on the same mesh.

Run: python benchmarks/speed.py [--cases trapezoid rectangle erodible plug-flow stall ...]
         [--repeat N] [--process] [--today] [--half-step] [--out benchmarks/results/speed]
     python benchmarks/speed.py --targets [--pairs ...] [--repeat 3] [--conditions quiet busy]
         [--baseline-src PATH] [--out benchmarks/results/speed_targets]

--targets times the erodible scenarios against their rigid twins as users wait for them
(``granflow run`` in a new process, figures included, whole-process wall and processor
times, medians of alternating runs, on the machine as it is and beside a busy process,
with the load average; ``speed_targets.py``): see there.

A is the paper's algorithm: fixed-point iterations (3.2), the ramp of section 3.1
(dt 1e-8 -> 1e-4, x1.1), tol 1e-4, w from u^n (3.6), run to t_end, on the same mesh
treatment (quality remeshing) and linear solver as B. B is granflow's default. With
--process, B is also run as a user runs it (`granflow run SCENARIO` in a new process, figures
and animation included) and that whole wall time is reported beside the time loop's. With
--today, A0 is also run: the first verified algorithm and code path (no quality remeshing,
UMFPACK). With --half-step, A_half (A with
dt_max = 5e-5) is also run and A and B are compared with it: it tells whose error a
distance between B and A is. For each case the JSON holds the
summaries, the wall-time ratio A/B (median over the repeats), the linear solves, and for
the collapses the stop times, runouts and the mean / max distance between the free
surfaces of A and B at every output time.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

from common.cases import CASES, PAPER, TODAY
from common.results import report, write_json
from common.runs import run_summary, surfaces_m


def run_process(scenario: str, overrides: list[str], out: Path) -> dict:
    """B as a user runs it: `granflow run` in a new process; its whole wall time."""
    sets = [arg for o in overrides for arg in ("--set", o)]
    command = [sys.executable, "-m", "granflow", "run", scenario, "--out", str(out), "--force",
               "--quiet", *sets]
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    summary = json.loads((out / "summary.json").read_text())
    return {"process_wall_time_s": wall, "loop_wall_time_s": summary["wall_time_s"],
            "status": summary["status"], "stop_time_s": summary.get("stop_time_s")}


def compare(name: str, repeat: int, out: Path, today: bool = False,
            half_step: bool = False, process: bool = False) -> dict:
    scenario, common, paper = CASES[name]
    result: dict = {"scenario": scenario, "common_overrides": common, "A_overrides": paper}
    variants = [("A", paper), ("B", [])]
    if today and paper is PAPER and name != "plug-flow":
        variants.append(("A0", [*paper, *TODAY]))
    if half_step and name != "plug-flow":      # whose error is a B-A distance? (A at dt/2)
        variants.append(("A_half", [*paper, "time.dt_max=5e-5"]))
    walls: dict[str, list[float]] = {label: [] for label, _ in variants}
    for k in range(repeat):
        for label, extra in variants:
            summary = run_summary(scenario, [*common, *extra], out / name / f"{label}{k}")
            walls[label].append(summary["wall_time_s"])
            result[label] = summary
            report(f"{name} {label} {k}", {x: summary[x] for x in (
                "status", "steps", "linear_solves", "wall_time_s", "stop_time_s",
                "runout_m", "velocity_relative_error_l2")})
        if process:
            timing = run_process(scenario, common, out / name / f"B_process{k}")
            result.setdefault("B_process", []).append(timing)
            report(f"{name} B as a process {k}", timing)
    a, b = result["A"], result["B"]
    result["wall_time_median_s"] = {k: statistics.median(v) for k, v in walls.items()}
    result["wall_times_s"] = walls
    result["speedup"] = result["wall_time_median_s"]["A"] / result["wall_time_median_s"]["B"]
    if process:
        result["B_process_wall_time_median_s"] = statistics.median(
            t["process_wall_time_s"] for t in result["B_process"])
    if "A0" in walls:
        result["speedup_vs_today"] = (result["wall_time_median_s"]["A0"]
                                      / result["wall_time_median_s"]["B"])
        result["surfaces_today"] = surfaces_m(out / name / "A00", out / name / "B0")
    if "A_half" in walls:
        result["surfaces_A_vs_A_half"] = surfaces_m(out / name / "A0", out / name / "A_half0")
        result["surfaces_B_vs_A_half"] = surfaces_m(out / name / "B0", out / name / "A_half0")
    result["linear_solves_ratio"] = a["linear_solves"] / max(b["linear_solves"], 1)
    if a.get("runout_m") is not None and b.get("runout_m") is not None:
        result["runout_difference_m"] = b["runout_m"] - a["runout_m"]
        if a.get("stop_time_s") and b.get("stop_time_s"):
            result["stop_time_relative_difference"] = b["stop_time_s"] / a["stop_time_s"] - 1
        result["surfaces"] = surfaces_m(out / name / "A0", out / name / "B0")
    return result


def main(argv: list[str]) -> None:
    if "--targets" in argv:
        from speed_targets import main as targets

        targets([a for a in argv if a != "--targets"])
        return
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cases", nargs="+", default=["trapezoid", "rectangle", "plug-flow"],
                        choices=sorted(CASES))
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/speed"))
    parser.add_argument("--process", action="store_true",
                        help="also time B as `granflow run` in its own process, outputs included")
    parser.add_argument("--today", action="store_true",
                        help="also run the first verified path (no quality remesh, UMFPACK)")
    parser.add_argument("--half-step", action="store_true",
                        help="also run A with dt_max = 5e-5 and compare A and B with it")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    table = ["| case | A loop (s) | B loop (s) | B process (s) | A/B | solves A / B |",
             "|---|---|---|---|---|---|"]
    for name in args.cases:
        result = compare(name, args.repeat, args.out / "runs", args.today, args.half_step,
                         args.process)
        write_json(args.out / f"{name}.json", result)
        medians = result["wall_time_median_s"]
        whole = result.get("B_process_wall_time_median_s")
        table.append(f"| {name} | {medians['A']:.1f} | {medians['B']:.1f} | "
                     f"{'-' if whole is None else f'{whole:.1f}'} | {result['speedup']:.2f} | "
                     f"{result['A']['linear_solves']} / {result['B']['linear_solves']} |")
    print("\n".join(table))


if __name__ == "__main__":
    main(sys.argv[1:])
