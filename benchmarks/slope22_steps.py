"""Benchmark: the slope study's 22-degree glass-bead row over 5 mm (``speed_targets.py``'s
``slope22``) with the error controller's cap at dt_max throughout against the slow flow's
raised cap, and what the raised cap changes in the quantities users read.

Run: python benchmarks/slope22_steps.py --run dt_max     (time.dt_max_slow = none: 1 ms)
     python benchmarks/slope22_steps.py --run slow       (time.dt_max_slow = 0.01,
                                                          time.slow_courant = 0.01)
     python benchmarks/slope22_steps.py [--out benchmarks/results/slope22_steps]
     python benchmarks/slope22_steps.py --progress slow   (a run so far, from its files)

Each ``--run TAG`` is one ``granflow run`` process into OUT/runs/TAG/rectangle-rigid, timed
from outside (``speed_targets.run``: processor time, wall time, load before it) and recorded
in OUT/slope22_steps.json; the runs may go side by side in separate commands. Without
``--run`` the recorded runs are compared (``collapse_runs.compare``, the first tag as the
reference): steps, iterations, remeshes, rejected steps, processor time, and the relative
changes of runout, flow duration, layer displaced and largest mobilised areas and the free
surfaces' mean and max distances at the output times, each judged against the accuracy
criteria of ``erodible_speed.CRITERIA``. Writes OUT/slope22_steps.json and
OUT/slope22_steps.md and prints the table. ``--progress TAG`` reads a run's
diagnostics.csv, finished or not, into OUT/progress-TAG.json: how far it went, its steps,
how many were longer than dt_max, the flowing fraction at its last step, and its summary's
status, remeshes and triangles (an interrupted run's summary holds them).

Prediction (written before the runs): at 22 degrees the glass beads still flow at 3 s, so
the cap rises only where the flow's RMS speed (the column, its deposit and the layer at
rest) carries it less than 0.14 mm in 1 ms, late in the run: 10-40 % fewer steps, processor
time down by less than the steps, every quantity within its criterion, and the row still
above 300 s of processor time.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd
from collapse_runs import compare
from common.results import read_results, report, write_results
from erodible_speed import CRITERIA, row
from speed_targets import PAIRS
from speed_targets import run as run_process

from granflow.io.run_dir import RunDir

SCENARIO, ROW = PAIRS["slope22"][1]
CAPS = {"dt_max": ["time.dt_max_slow=none"],
        "slow": ["time.dt_max_slow=0.01", "time.slow_courant=0.01"]}
COST = ["process_cpu_time_s", "process_wall_time_s", "load_before", "steps",
        "rejected_steps", "nonlinear_iterations", "remeshes", "n_triangles", "status",
        "stop_time_s", "runout_m"]


def table(record: dict, reference: str) -> list[str]:
    lines = ["| cap | processor time (s) | wall time (s), load | steps | rejected | iterations "
             "| remeshes | changes (%) | surfaces, mean / max "
             "(mm) | within |", "|---|---|---|---|---|---|---|---|---|---|"]
    for tag, run in record["runs"].items():
        c = record.get("changes", {}).get(tag)
        changes = (", ".join(f"{k} {v:+.2f}" for k, v in c["changes_percent"].items())
                   if c else "-")
        surfaces = (f"{c['surfaces_mm']['surface_mean_mm']:.2f} / "
                    f"{c['surfaces_mm']['surface_max_mm']:.2f}" if c else "-")
        within = ("all" if all(c["within"].values()) else
                  "not " + ", ".join(k for k, v in c["within"].items() if not v)) if c else "-"
        lines.append(f"| {tag} | {run['process_cpu_time_s']:.0f} | "
                     f"{run['process_wall_time_s']:.0f}, {run['load_before']:.1f} | "
                     f"{run['steps']} | {run['rejected_steps']} | "
                     f"{run['nonlinear_iterations']} | {run['remeshes']} | {changes} | "
                     f"{surfaces} | {within} |")
    return [*lines, "", f"(changes against `{reference}`; criteria {CRITERIA})"]


def progress(root: Path) -> dict:
    """A run's steps so far (diagnostics.csv: one row a step), and those above dt_max."""
    diag = pd.read_csv(root / "diagnostics.csv")
    raised = diag["t"][diag["dt"] > 1e-3 * (1 + 1e-9)]
    return {"t_s": float(diag["t"].iloc[-1]), "steps": len(diag),
            "steps_above_dt_max": len(raised),
            "last_step_above_dt_max_t_s": float(raised.max()) if len(raised) else None,
            "iterations": int(diag["iterations"].sum()),
            "flowing_fraction_last": float(diag["flowing_fraction"].iloc[-1])} | {
                k: RunDir.summary(root).get(k) for k in ("status", "remeshes", "remeshed_moves",
                                                         "rejected_steps", "n_triangles")}


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", choices=list(CAPS), help="run this cap (else: compare)")
    parser.add_argument("--progress", choices=list(CAPS), help="a run so far, from its files")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/slope22_steps"))
    args = parser.parse_args(argv)
    if args.progress:
        found = progress(args.out / "runs" / args.progress / SCENARIO)
        report(args.progress, found)
        write_results(args.out, f"progress-{args.progress}", found)
        return
    if args.run:
        result = run_process(SCENARIO, [*ROW, *CAPS[args.run]],
                             args.out / "runs" / args.run / SCENARIO)
        report(args.run, result)
        record = read_results(args.out / "slope22_steps.json")   # read again: runs in parallel
        record.setdefault("runs", {})[args.run] = {k: result.get(k) for k in COST} | {
            "overrides": [*ROW, *CAPS[args.run]]}
        write_results(args.out, "slope22_steps", record)
        return
    record = read_results(args.out / "slope22_steps.json")
    reference, *others = [t for t in CAPS if t in record.get("runs", {})]
    pairs = {tag: compare(reference, tag, [SCENARIO], args.out / "runs")[SCENARIO]
             for tag in others}
    record["changes"] = {tag: row(p, reference, tag) for tag, p in pairs.items()}
    write_results(args.out, "slope22_steps", record, table(record, reference), show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
