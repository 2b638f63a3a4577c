"""Benchmark: rectangles of growing aspect ratio on a rigid bed, run to rest.

Run: python benchmarks/tall_columns.py [--ratios 0.5 1 2 3 4] [--width 0.1]
         [--set key=value ...] [--out benchmarks/results/tall_columns]

Each column (l0 = --width, h0 = ratio x l0, the rectangle-rigid defaults otherwise) runs
into OUT/runs/hRATIO; OUT/tall_columns.json and OUT/tall_columns.md give status, stop
time, runout, remeshes, the worst area change of a remesh (after its own area fix), the
worst area its boundary simplification lost (restored), the accumulated area correction of
the volume fix over the run, the worst triangle quality at the end and the wall time.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from common.results import read_results, report, write_json, write_markdown

import granflow
from granflow.config import load_config
from granflow.io.run_dir import RunDir

KEYS = ["status", "message", "t_final", "steps", "rejected_steps", "linear_solves",
        "wall_time_s", "stop_time_s", "runout_m", "n_triangles", "remeshes",
        "remesh_area_change_max", "remesh_area_restored_max", "area_correction_total",
        "area_correction_net", "min_triangle_quality"]


def table(results: dict[str, dict]) -> str:
    lines = ["| h0/l0 | status | stop (s) | runout (m) | remeshes | worst remesh area change | "
             "worst restored by remesh | sum of area fixes | min quality | wall (s) |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for ratio, r in sorted(results.items(), key=lambda kv: float(kv[0])):
        stop = r["stop_time_s"]
        lines.append(
            f"| {ratio} | {r['status']} | {'-' if stop is None else f'{stop:.3f}'} | "
            f"{r['runout_m']:.4f} | {r['remeshes']} | {r['remesh_area_change_max']:.1e} | "
            f"{r['remesh_area_restored_max']:.1e} | {r['area_correction_total']:.2e} | "
            f"{r['min_triangle_quality']:.2f} | {r['wall_time_s']:.0f} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--ratios", nargs="+", type=float, default=[0.5, 1.0, 2.0, 3.0, 4.0])
    parser.add_argument("--width", type=float, default=0.1)
    parser.add_argument("--set", dest="extra", action="append", default=[])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/tall_columns"))
    args = parser.parse_args()
    store = args.out / "tall_columns.json"
    results = read_results(store)
    for ratio in args.ratios:
        overrides = [f"geometry.width={args.width!r}", f"geometry.height={ratio * args.width!r}",
                     "time.t_end=3.0", *args.extra]
        config = load_config("rectangle-rigid", overrides)
        run_dir = granflow.run(config, out=args.out / "runs" / f"h{ratio:g}", force=True)
        summary = RunDir.summary(run_dir.root)
        results[f"{ratio:g}"] = {k: summary.get(k) for k in KEYS} | {"overrides": overrides}
        report(f"h0/l0 = {ratio:g}", results[f"{ratio:g}"])
        write_json(store, results)
        write_markdown(args.out / "tall_columns.md", table(results))
    print(table(results))


if __name__ == "__main__":
    main()
