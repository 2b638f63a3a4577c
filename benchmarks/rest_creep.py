"""Benchmark: what decides a run's rest stop, from its diagnostics.csv.

Run: python benchmarks/rest_creep.py RUN_DIR [RUN_DIR ...] [--from 0.7] [--to 1.25]
         [--window 0.05] [--out benchmarks/results/cylinder_rest/rest_creep]
For each finished run directory (the folder's name is its label, its parent's name too when
two share one): its summary's rest stop, runout and steps; when the flow ends
(``duration_s``: flowing fraction below 1 %, the measure the speed work compares) and when
the front settles to within 1 mm; and, in windows of ``--window`` seconds between
``--from`` and ``--to``, the largest flowing fraction against the rest rule's
``time.rest_fraction``, the largest speed and the front's mean speed. A stop decided by a
foot creeping about the rule's threshold shows as a flowing fraction hovering at
``rest_fraction`` with a front moving by millimetres per second while the flow has ended.
Writes OUT.json and OUT.md.
"""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

import numpy as np
from common.results import write_json, write_markdown

from granflow.diagnostics.front import flow_duration, settle_time
from granflow.io.diagnostics import read_diagnostics
from granflow.io.run_dir import RunDir


def creep(root: Path, start: float, end: float, window: float) -> dict:
    """The run's stop, flow duration and creep windows (see the module's docstring)."""
    summary = RunDir.summary(root)
    rest_fraction = tomllib.loads((root / "config.toml").read_text())["time"]["rest_fraction"]
    diag = read_diagnostics(root)
    t, fraction = diag["t"].to_numpy(), diag["flowing_fraction"].to_numpy()
    front, speed = diag["front_x"].to_numpy(), diag["max_speed"].to_numpy()
    windows = []
    for lo in np.arange(start, end - 1e-9, window):
        inside = (t > lo) & (t <= lo + window)
        if np.count_nonzero(inside) < 2:
            continue
        ti, xi = t[inside], front[inside]
        windows.append({"t0": round(float(lo), 6), "t1": round(float(lo + window), 6),
                        "flowing_fraction_max": float(fraction[inside].max()),
                        "above_rest_fraction": bool(fraction[inside].max() > rest_fraction),
                        "max_speed_max_m_s": float(speed[inside].max()),
                        "front_speed_mean_m_s": float((xi[-1] - xi[0]) / (ti[-1] - ti[0]))})
    above = np.flatnonzero(fraction > rest_fraction)
    return {"status": summary.get("status"), "stop_time_s": summary.get("stop_time_s"),
            "runout_m": summary.get("runout_m"), "steps": summary.get("steps"),
            "nonlinear_iterations": summary.get("nonlinear_iterations"),
            "duration_s": flow_duration(t, fraction),
            "front_settle_time_s": settle_time(t, front),
            "rest_fraction": rest_fraction,
            "last_above_rest_fraction_s": float(t[above[-1]]) if above.size else None,
            "windows": windows}


def table(results: dict[str, dict]) -> list[str]:
    lines = ["| run | rest stop (s) | duration (s) | front settles (s) | runout (m) | steps |",
             "|---|---|---|---|---|---|"]
    for name, r in results.items():
        lines.append(f"| {name} | {r['stop_time_s']} | {r['duration_s']} | "
                     f"{r['front_settle_time_s']} | {r['runout_m']} | {r['steps']} |")
    for name, r in results.items():
        lines += ["", f"{name}: windows (flowing fraction max against {r['rest_fraction']}, "
                  "largest speed, front's mean speed)", "",
                  "| t (s) | flowing fraction max | largest speed (mm/s) | front (mm/s) |",
                  "|---|---|---|---|"]
        lines += [f"| {w['t0']:.2f}-{w['t1']:.2f} | {w['flowing_fraction_max']:.5f} | "
                  f"{1e3 * w['max_speed_max_m_s']:.2f} | {1e3 * w['front_speed_mean_m_s']:.2f} |"
                  for w in r["windows"]]
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("runs", nargs="+", type=Path)
    parser.add_argument("--from", dest="start", type=float, default=0.7)
    parser.add_argument("--to", dest="end", type=float, default=1.25)
    parser.add_argument("--window", type=float, default=0.05)
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/cylinder_rest/rest_creep"))
    args = parser.parse_args()
    names = [root.name for root in args.runs]
    if len(set(names)) < len(names):
        names = [f"{root.parent.name}/{root.name}" for root in args.runs]
    results = {name: creep(root, args.start, args.end, args.window)
               for name, root in zip(names, args.runs, strict=True)}
    write_json(args.out.with_suffix(".json"), results)
    write_markdown(args.out.with_suffix(".md"), table(results), show=True)


if __name__ == "__main__":
    main()
