"""Benchmark: the critical-state packing (docs/model.md, "Packing fraction") in a collapse.

Run: python benchmarks/packing.py validation [--scenario rectangle-rigid] [--t-end T]
         [--cases incompressible loose dense]
     python benchmarks/packing.py cost [--scenario rectangle-rigid] [--t-end 0.2] [--pairs 3]
         [--out benchmarks/results/packing]

``validation``: the same collapse incompressible (packing = "none"), from a loose column
(phi_0 = phi_c - 0.02) and from a dense one (phi_0 = phi_c + 0.02), phi_0 set by
material.density = rho_s phi_0: runout, the times the collapse and its front stop, the
grains' mass error (largest over the run), phi's extremes, steps, nonlinear iterations and
processor time. The prediction is OUT/prediction.md, written before the runs. Writes
OUT/validation.json and .md.

``cost``: the cost of a step with the packing against the same run without it, in pairs
run one after the other (none, packing, none, packing, ...; processor time of this process,
``resource.getrusage``, and nonlinear iterations and linear solves per step, medians over
the pairs), with the machine's load average beside it. Writes OUT/cost.json and .md.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
from pathlib import Path

from common.results import read_results, report, write_results

import granflow
from granflow.config import load_config
from granflow.io.run_dir import RunDir

KEYS = ["status", "t_final", "stop_time_s", "front_stop_time_s", "runout_m", "steps",
        "rejected_steps", "nonlinear_iterations", "linear_solves", "volume_relative_error",
        "mass_relative_error", "mass_relative_error_max", "packing_min", "packing_max",
        "remeshes"]
CRITICAL = 0.60           # packing_critical's default (phi_c)
GRAIN_DENSITY = 2500.0    # material.grain_density's default (rho_s)


def run(scenario: str, overrides: list[str], out: Path) -> dict:
    """One run into OUT; its summary's KEYS and the processor time it took."""
    config = load_config(scenario, [*overrides, "output.progress=false"])
    before = resource.getrusage(resource.RUSAGE_SELF)
    run_dir = granflow.run(config, out=out, force=True)
    after = resource.getrusage(resource.RUSAGE_SELF)
    summary = RunDir.summary(run_dir.root)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {k: summary.get(k) for k in KEYS} | {"cpu_s": cpu, "overrides": overrides}


def packing(start: float) -> list[str]:
    return ["material.packing=critical-state",
            f"material.density={GRAIN_DENSITY * start!r}"]


CASES = {"incompressible": [],
         "loose": packing(round(CRITICAL - 0.02, 4)),
         "dense": packing(round(CRITICAL + 0.02, 4))}


def validation(args: argparse.Namespace) -> None:
    common = [f"time.t_end={args.t_end!r}"] if args.t_end else []
    rows = read_results(args.out / "validation.json").get("rows", {}) if args.cases else {}
    for name in args.cases or CASES:
        overrides = CASES[name]
        rows[name] = run(args.scenario, [*common, *overrides], args.out / "runs" / name)
        report(name, rows[name])
        lines = ["| case | runout (m) | stop (s) | front stops (s) | mass error max | "
                 "phi min / max | steps | cpu (s) |", "|---|---|---|---|---|---|---|---|"]
        for case, r in rows.items():
            mass = r["mass_relative_error_max"]
            phi = (f"{r['packing_min']:.4f} / {r['packing_max']:.4f}"
                   if r["packing_min"] is not None else "-")
            lines.append(
                f"| {case} | {r['runout_m']:.4f} | {r['stop_time_s']} | "
                f"{r['front_stop_time_s']} | {'-' if mass is None else f'{mass:.2e}'} | "
                f"{phi} | {r['steps']} | {r['cpu_s']:.0f} |")
        write_results(args.out, "validation", {"scenario": args.scenario, "rows": rows},
                      lines, show=True)


def cost(args: argparse.Namespace) -> None:
    common = [f"time.t_end={args.t_end!r}"]
    pairs: list[dict] = []
    for k in range(args.pairs):
        pair = {}
        for name in ("incompressible", "dense"):
            pair[name] = run(args.scenario, [*common, *CASES[name]],
                             args.out / "runs" / f"cost-{name}")
            pair[name]["load_average"] = os.getloadavg()[0]
            report(f"pair {k} {name}", pair[name])
        pairs.append(pair)

    def per_step(name: str, key: str) -> float:
        return statistics.median(p[name][key] / p[name]["steps"] for p in pairs)

    ratios = {key: per_step("dense", key) / per_step("incompressible", key)
              for key in ("cpu_s", "nonlinear_iterations", "linear_solves")}
    lines = ["| per step (median over pairs) | incompressible | packing | ratio |",
             "|---|---|---|---|"]
    for key, ratio in ratios.items():
        lines.append(f"| {key} | {per_step('incompressible', key):.4g} | "
                     f"{per_step('dense', key):.4g} | {ratio:.3f} |")
    loads = [p[n]["load_average"] for p in pairs for n in p]
    lines.append(f"\nload average (1 min) beside the runs: {min(loads):.1f}-{max(loads):.1f}")
    write_results(args.out, "cost", {"scenario": args.scenario, "t_end": args.t_end,
                                     "pairs": pairs, "ratios": ratios}, lines, show=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("study", choices=["validation", "cost"])
    parser.add_argument("--scenario", default="rectangle-rigid")
    parser.add_argument("--t-end", type=float, default=None)
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--cases", nargs="+", choices=list(CASES),
                        help="validation: run these cases only, keeping the others' rows")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/packing"))
    args = parser.parse_args()
    if args.study == "cost" and args.t_end is None:
        args.t_end = 0.2
    (validation if args.study == "validation" else cost)(args)


if __name__ == "__main__":
    main()
