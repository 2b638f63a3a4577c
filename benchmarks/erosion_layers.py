"""Benchmark: the erodible layer's resolution (``mesh.layer_cells`` = cells across it,
``mesh.layer_aspect`` = their length along it over their height) and which of runout,
duration and eroded area it has converged.

Run: python benchmarks/erosion_layers.py [--cells 2 4 8 16] [--aspects 1] [--slopes 0]
         [--scenario trapezoid-erodible] [--set key=value ...]
         [--out benchmarks/results/erosion_layers] [--collect]
     python benchmarks/erosion_layers.py --against RUN_DIR [RUN_DIR ...] [--slopes 0]

Each run goes to OUT/runs/slopeS-cellsN, a normal run directory, checkpointed every 100
steps. A finished run is not run again, one with a checkpoint is resumed
(``granflow.resume``): rerunning the command continues a study that was stopped.
``--collect`` runs nothing and tabulates what is there. OUT/erosion_layers.json holds the
summaries' figures, OUT/erosion_layers.md the table with each figure's change from the
previous (coarser) level, then every run against the finest isotropic run of its slope (the
reference) with the accuracy it must keep (ACCURACY: runout 1 %, flow duration 2 %,
displaced and mobilised areas 2 % and 5 %). ``--against`` runs nothing: it compares the
given run directories (e.g. `granflow run trapezoid-erodible` at its defaults) with that
reference and writes OUT/against_reference.json.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from common.results import read_results, report, write_json, write_markdown
from common.runs import collected, flow_duration, run_or_continue

KEYS = ["status", "t_final", "steps", "nonlinear_iterations", "wall_time_s", "n_triangles",
        "remeshes", "stop_time_s", "front_stop_time_s", "runout_m", "column_front_m",
        "layer_displaced_area_m2", "layer_mobilised_area_max_m2", "erosion_depth_max_m",
        "layer_area_drift", "layer_area_drift_max", "volume_relative_error"]
COMPARED = ["runout_m", "column_front_m", "duration_s", "stop_time_s",
            "layer_displaced_area_m2", "layer_mobilised_area_max_m2", "layer_area_drift_max"]
ACCURACY = {"runout_m": 0.01, "duration_s": 0.02, "layer_displaced_area_m2": 0.02,
            "layer_mobilised_area_max_m2": 0.05}      # relative, against the reference


def run_name(slope: float, cells: int, aspect: float) -> str:
    """OUT/runs/NAME of a level (isotropic runs keep their names)."""
    return f"slope{slope:g}-cells{cells}" + ("" if aspect == 1 else f"-aspect{aspect:g}")


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
    for r in sorted(results.values(), key=lambda r: (r["slope"], r.get("aspect", 1.0),
                                                     r["cells"])):
        if previous is not None and (previous["slope"], previous.get("aspect", 1.0)) != (
                r["slope"], r.get("aspect", 1.0)):
            previous = None
        cells = [f"{r['slope']:g}", _cells(r), str(r["n_triangles"]),
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


def _cells(row: dict) -> str:
    aspect = row.get("aspect", 1.0)
    return str(row["cells"]) + ("" if aspect == 1 else f" x {aspect:g}")


def against_reference(results: dict[str, dict]) -> str:
    """Markdown: every finished run against the finest isotropic run of its slope, each
    figure's relative difference and whether it keeps ACCURACY."""
    head = ["slope (deg)", "layer cells (x aspect)", "triangles", "wall time (s)",
            *(f"{k} (<= {100 * v:g} %)" for k, v in ACCURACY.items()), "within"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    done = [r for r in results.values() if r["status"] in ("completed", "stopped")]
    for slope in sorted({r["slope"] for r in done}):
        rows = [r for r in done if r["slope"] == slope]
        isotropic = [r for r in rows if r.get("aspect", 1.0) == 1]
        if not isotropic:
            continue
        ref = max(isotropic, key=lambda r: r["cells"])
        for r in sorted(rows, key=lambda r: (r["cells"], r.get("aspect", 1.0))):
            if r is ref:
                continue
            cells = [f"{slope:g}", _cells(r), str(r["n_triangles"]),
                     f"{r['wall_time_s']:.0f}" if r["wall_time_s"] else "-"]
            ok = True
            for key, tol in ACCURACY.items():
                value, target = r.get(key), ref.get(key)
                if value is None or not target:
                    cells.append("-")
                    ok = False
                    continue
                rel = (value - target) / target
                ok = ok and abs(rel) <= tol
                cells.append(f"{100 * rel:+.2f} %")
            cells.append("yes" if ok else "no")
            lines.append("| " + " | ".join(cells) + " |")
        lines.append(f"\nReference: {ref['cells']} isotropic cells at {slope:g} degrees, "
                     f"{ref['n_triangles']} triangles.\n")
    return "\n".join(lines) + "\n"


def against(dirs: list[Path], results: dict[str, dict], slope: float, out: Path) -> dict:
    """Each run directory's ACCURACY figures relative to the finest isotropic run of
    ``slope`` in ``results``, into OUT/against_reference.json (keyed by folder name)."""
    isotropic = [r for r in results.values() if r.get("slope") == slope
                 and r.get("aspect", 1.0) == 1 and r["status"] in ("completed", "stopped")]
    ref = max(isotropic, key=lambda r: r["cells"])
    found = read_results(out / "against_reference.json")
    for folder in dirs:
        summary = collected(folder)
        if summary is None:
            raise SystemExit(f"{folder}: no finished run there")
        row = row_of(summary, folder, [])
        rel = {k: (row[k] - ref[k]) / ref[k] for k in ACCURACY if row.get(k) and ref.get(k)}
        found[folder.name] = {"reference": f"{ref['cells']} isotropic cells at {slope:g} deg",
                              "n_triangles": row["n_triangles"], "relative": rel,
                              "within": all(abs(rel.get(k, 1.0)) <= t
                                            for k, t in ACCURACY.items())}
        report(folder.name, found[folder.name])
    write_json(out / "against_reference.json", found)
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cells", type=int, nargs="+", default=[2, 4, 8, 16])
    parser.add_argument("--aspects", type=float, nargs="+", default=[1.0])
    parser.add_argument("--slopes", type=float, nargs="+", default=[0.0])
    parser.add_argument("--scenario", default="trapezoid-erodible")
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/erosion_layers"))
    parser.add_argument("--collect", action="store_true")
    parser.add_argument("--against", type=Path, nargs="+", default=[], metavar="RUN_DIR")
    args = parser.parse_args()
    results_file = args.out / "erosion_layers.json"
    results = read_results(results_file)
    if args.against:
        against(args.against, results, args.slopes[0], args.out)
        return
    levels = [(s, c, a) for s in args.slopes for a in args.aspects for c in args.cells]
    for slope, cells, aspect in levels:
        name = run_name(slope, cells, aspect)
        out = args.out / "runs" / name
        overrides = [*args.overrides, f"mesh.layer_cells={cells}",
                     f"mesh.layer_aspect={aspect!r}",
                     f"geometry.slope_deg={slope!r}", "output.checkpoint_every=100"]
        if args.collect:
            summary = collected(out)
            if summary is None:
                continue
            row = row_of(summary, out, overrides)
        else:
            row = run_case(args.scenario, overrides, out)
        results[name] = row | {"slope": slope, "cells": cells, "aspect": aspect}
        report(name, results[name])
        write_json(results_file, results)
        write_markdown(args.out / "erosion_layers.md",
                       table(results) + "\n" + against_reference(results))
    print(table(results) + "\n" + against_reference(results))


if __name__ == "__main__":
    main()
