"""Benchmark: the erodible layer's resolution (``mesh.layer_cells`` = cells across it) and
which of runout, duration and eroded area it has converged.

Run: python benchmarks/erosion_layers.py [--cells 2 4 8 16] [--slopes 0]
         [--scenario trapezoid-erodible] [--set key=value ...]
         [--out benchmarks/results/erosion_layers] [--collect]

Each run goes to OUT/runs/slopeS-cellsN, a normal run directory, checkpointed every 100
steps. A finished run is not run again, one with a checkpoint is resumed
(``granflow.resume``): rerunning the command continues a study that was stopped.
``--collect`` runs nothing and tabulates what is there. OUT/erosion_layers.json holds the
summaries' figures, OUT/erosion_layers.md the table with each figure's change from the
previous (coarser) level.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from common.runs import collected, flow_duration, run_or_continue

from granflow.io.run_dir import atomic_write_text

KEYS = ["status", "t_final", "steps", "nonlinear_iterations", "wall_time_s", "n_triangles",
        "remeshes", "stop_time_s", "front_stop_time_s", "runout_m", "column_front_m",
        "layer_displaced_area_m2", "layer_mobilised_area_max_m2", "erosion_depth_max_m",
        "layer_area_drift", "layer_area_drift_max", "volume_relative_error"]
COMPARED = ["runout_m", "column_front_m", "duration_s", "stop_time_s",
            "layer_displaced_area_m2", "layer_mobilised_area_max_m2", "layer_area_drift_max"]
def run_case(scenario: str, overrides: list[str], out: Path) -> dict:
    """The run in ``out``: kept when finished, continued from its checkpoint, else run."""
    summary = run_or_continue(scenario, overrides, out)
    return row_of(summary, out, overrides)


def row_of(summary: dict, out: Path, overrides: list[str]) -> dict:
    """The summary's figures and the flow's duration (below 1 % flowing)."""
    return {k: summary.get(k) for k in KEYS} | {"duration_s": flow_duration(out),
                                                "overrides": overrides}


def table(results: dict[str, dict]) -> str:
    """Markdown: one row per run, each compared figure with its change from the row above
    (same slope, the next coarser layer)."""
    head = ["slope (deg)", "layer cells", "triangles", "wall time (s)", "status"] + COMPARED
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    previous: dict | None = None
    for r in sorted(results.values(), key=lambda r: (r["slope"], r["cells"])):
        if previous is not None and previous["slope"] != r["slope"]:
            previous = None
        cells = [f"{r['slope']:g}", str(r["cells"]), str(r["n_triangles"]),
                 f"{r['wall_time_s']:.0f}" if r["wall_time_s"] else "-", r["status"]]
        if r["status"] not in ("completed", "stopped"):     # mid-run figures: not compared
            cells[-1] += f" at t = {r['t_final']:.3f} s"
            lines.append("| " + " | ".join(cells + ["-"] * len(COMPARED)) + " |")
            continue
        for key in COMPARED:
            value = r.get(key)
            text = "-" if value is None else f"{value:.4g}"
            old = previous.get(key) if previous else None
            if value is not None and old:
                text += f" ({100 * (value - old) / old:+.1f} %)"
            cells.append(text)
        lines.append("| " + " | ".join(cells) + " |")
        previous = r
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, nargs="+", default=[2, 4, 8, 16])
    parser.add_argument("--slopes", type=float, nargs="+", default=[0.0])
    parser.add_argument("--scenario", default="trapezoid-erodible")
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/erosion_layers"))
    parser.add_argument("--collect", action="store_true")
    args = parser.parse_args()
    results_file = args.out / "erosion_layers.json"
    results = json.loads(results_file.read_text()) if results_file.is_file() else {}
    for slope in args.slopes:
        for cells in args.cells:
            name = f"slope{slope:g}-cells{cells}"
            out = args.out / "runs" / name
            overrides = [*args.overrides, f"mesh.layer_cells={cells}",
                         f"geometry.slope_deg={slope!r}", "output.checkpoint_every=100"]
            if args.collect:
                summary = collected(out)
                if summary is None:
                    continue
                row = row_of(summary, out, overrides)
            else:
                row = run_case(args.scenario, overrides, out)
            results[name] = row | {"slope": slope, "cells": cells}
            print(name, json.dumps(results[name]), flush=True)
            atomic_write_text(results_file, json.dumps(results, indent=2))
            atomic_write_text(args.out / "erosion_layers.md", table(results))
    print(table(results))


if __name__ == "__main__":
    main()
