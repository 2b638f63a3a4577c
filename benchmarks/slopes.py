"""Benchmark: collapses on sloping beds, rigid and erodible, both shapes.

Run: python benchmarks/slopes.py [--slopes 0 10 16 22] [--beds rigid erodible]
         [--shapes trapezoid rectangle] [--set key=value ...] [--out benchmarks/results/slopes]
         [--collect]

--collect runs nothing: it reads the summaries of the selected runs now in OUT/runs
(for example runs continued with `granflow resume OUT/runs/NAME` after an interruption)
into slopes.json and slopes.md.

Each run goes to OUT/runs/SHAPE-BED-SLOPE (a normal run directory); OUT/slopes.json collects
status, stop time, runout (the front of the mass, over a layer the eroding mass) and
counters, and OUT/slopes.md the table of runout, stop time and erodible/rigid runout ratio
against slope (the ratio once the erodible run's front is at rest, even where a few cells
behind it still creep). The erodible variants are the scenarios' columns standing on the 5 mm layer
of `trapezoid-erodible` (h0 including the layer, the layer's end at `bed_length`), with its
surface tension and mesh velocity; every run uses `boundary.normal_load = "reaction"` (the
friction load whose sliding-block error is under 0.5 %); nothing else changes with slope.
`geometry.bed_length` is 1.3 times the rigid-bed runout at the same slope (run the rigid
beds first), so that the layer does not end under the flow.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from common.results import read_results, report, write_json, write_markdown

import granflow
from granflow.config import load_config
from granflow.io.run_dir import RunDir

KEYS = ["status", "message", "t_final", "steps", "linear_solves", "wall_time_s",
        "stop_time_s", "runout_m", "runout_1mm_m", "volume_relative_error", "n_triangles",
        "remeshes", "surface_tension_steps", "front_stop_time_s"]
ERODIBLE = ["geometry.erodible_thickness=0.005", "numerics.mesh_velocity=elastic",
            "surface_tension.enabled=true", "mesh.layer_cells=2"]
COMMON = ["boundary.normal_load=reaction"]   # the basal friction decides the runout on a slope
SCENARIO = {"trapezoid": "trapezoid-rigid", "rectangle": "rectangle-rigid"}


def overrides(shape: str, bed: str, slope: float, rigid_runout: float | None) -> list[str]:
    """The layer ends 30 % beyond the rigid-bed runout at the same slope (when known)."""
    length = max(1.0, 1.3 * rigid_runout) if rigid_runout else 1.0 + 0.05 * slope
    extra = [*COMMON, f"geometry.slope_deg={slope!r}", "time.t_end=3.0"]
    if bed == "erodible":          # (a rigid bed has no bed_length: it is unbounded)
        height = 0.25 if shape == "trapezoid" else 0.14
        extra += [*ERODIBLE, f"geometry.height={height + 0.005!r}",
                  f"geometry.bed_length={length!r}"]
    return extra


def table(results: dict[str, dict]) -> str:
    lines = ["| shape | slope (deg) | runout rigid (m) | runout erodible (m) | ratio | "
             "stop rigid (s) | stop erodible (s) | erodible front at rest (s) |",
             "|---|---|---|---|---|---|---|---|"]
    keys = sorted({(r["shape"], r["slope"]) for r in results.values()})
    for shape, slope in keys:
        rigid = results.get(f"{shape}-rigid-{slope:g}", {})
        ero = results.get(f"{shape}-erodible-{slope:g}", {})
        settled = ero.get("status") == "stopped" or ero.get("front_stop_time_s") is not None
        ratio = (ero["runout_m"] / rigid["runout_m"] if settled and ero.get("runout_m")
                 and rigid.get("runout_m") else None)

        def fmt(run: dict, key: str) -> str:
            if run.get("status") in ("failed", "unfinished"):
                return f"{run['status']} at {run['t_final']:.3f} s"
            x = run.get(key)
            if x is None and key == "stop_time_s" and run:
                return f"flowing at {run['t_final']:.2f} s"
            return "-" if x is None else format(x, ".3f")

        lines.append(f"| {shape} | {slope:g} | {fmt(rigid, 'runout_m')} | "
                     f"{fmt(ero, 'runout_m')} | {'-' if ratio is None else f'{ratio:.3f}'} | "
                     f"{fmt(rigid, 'stop_time_s')} | {fmt(ero, 'stop_time_s')} | "
                     f"{fmt(ero, 'front_stop_time_s')} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--slopes", nargs="+", type=float, default=[0.0, 10.0, 16.0, 22.0])
    parser.add_argument("--beds", nargs="+", default=["rigid", "erodible"])
    parser.add_argument("--shapes", nargs="+", default=["trapezoid", "rectangle"])
    parser.add_argument("--set", dest="extra", action="append", default=[])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/slopes"))
    parser.add_argument("--collect", action="store_true",
                        help="read the summaries of existing runs instead of running")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    store = args.out / "slopes.json"
    results = read_results(store)   # rigid runouts
    for shape in args.shapes:
        for bed in args.beds:
            for slope in args.slopes:
                name = f"{shape}-{bed}-{slope:g}"
                if args.collect:
                    summary_file = args.out / "runs" / name / "summary.json"
                    summary = (json.loads(summary_file.read_text())
                               if summary_file.exists() else {"status": "running"})
                    if summary["status"] != "running":     # (a live run is not collected)
                        results = _store(args.out, name, {k: summary.get(k) for k in KEYS}
                                         | {"shape": shape, "bed": bed, "slope": slope})
                    continue
                rigid = results.get(f"{shape}-rigid-{slope:g}", {}).get("runout_m")
                config = load_config(SCENARIO[shape], [*overrides(shape, bed, slope, rigid),
                                                       *args.extra])
                run_dir = granflow.run(config, out=args.out / "runs" / name, force=True)
                summary = RunDir.summary(run_dir.root)
                results = _store(args.out, name, {k: summary.get(k) for k in KEYS} | {
                    "shape": shape, "bed": bed, "slope": slope})
                report(name, results[name])
    print(table(results))


def _store(out: Path, name: str, row: dict) -> dict[str, dict]:
    """Write one run's row into OUT/slopes.json (and the table), re-reading the file first:
    another invocation (a long run, a --collect) may have written rows since this one
    started."""
    store = out / "slopes.json"
    results = read_results(store)
    results[name] = row
    write_json(store, results)
    write_markdown(out / "slopes.md", table(results))
    return results


if __name__ == "__main__":
    main()
