"""Benchmark: what the erodible runs' speed-ups changed in their results, against the earlier
code and against the finest layer resolution.

Run: PYTHONPATH=OLD/src python benchmarks/collapse_runs.py --scenarios trapezoid-erodible
         cylinder-erodible trapezoid-rigid cylinder-rigid --tag base --out DIR   (commit 284e367)
     python benchmarks/collapse_runs.py --scenarios ... --tag head --out DIR \\
         --set time.dt_max_slow=none                                  (steps of dt_max)
     python benchmarks/collapse_runs.py --scenarios ... --tag slow --out DIR \\
         --set time.dt_max_slow=0.01 --set time.slow_courant=0.01     (the erodible defaults)
     python benchmarks/collapse_runs.py --compare base head --scenarios ... --out DIR
     python benchmarks/collapse_runs.py --compare head slow --scenarios ... --out DIR
     python benchmarks/erodible_speed.py --runs DIR [--out benchmarks/results/erodible_speed]

Reads DIR/base-vs-head.json (the folds' and the tracking's change: the earlier code's runs
against this code's) and DIR/head-vs-slow.json (the steps where the flow is slow: time.dt_max
throughout against time.dt_max_slow), and the finest layer resolution's row of
``erosion_layers.py`` (8 isotropic cells across the layer). Writes OUT/erodible_speed.json:
per comparison and run the counts, the relative changes (%) of runout, duration and the
layer's amounts, the largest mean and max distance (mm) between the free surfaces at the
output times and whether each is within the accuracy criteria (``CRITERIA``); and the
erodible trapezoid of each code against the finest layer. OUT/erodible_speed.md holds the
tables.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from common.results import write_results

REFERENCE = Path(__file__).parent / "results/erosion_layers/erosion_layers.json"
REFERENCE_ROW = "slope0-cells8"          # trapezoid-erodible, 8 isotropic cells across
# relative (%) changes and surface distances (mm) within which a result holds: the speed
# work's targets (docs/performance.md, the time integrator) and the layer's accuracy
CRITERIA = {"runout_m": 1.0, "duration_s": 2.0, "layer_displaced": 2.0,
            "layer_mobilised": 5.0, "surface_mean_mm": 1.0, "surface_max_mm": 3.0}
COUNTS = ["steps", "nonlinear_iterations", "remeshes", "rejected_steps", "stop_time_s",
          "runout_m", "duration_s"]


def layer_key(key: str) -> str | None:
    """The criterion of a summary's layer amount (area in plane strain, volume in r-z)."""
    if key.startswith("layer_displaced"):
        return "layer_displaced"
    return "layer_mobilised" if key.startswith("layer_mobilised") else None


def row(pair: dict, before: str, after: str) -> dict:
    """One run's comparison: counts both ways, changes (%), surfaces (mm), verdicts."""
    changes = {(layer_key(k) or k): 100 * v for k, v in pair["relative_changes"].items()}
    gaps = pair["free_surfaces"].values()
    surfaces = {"surface_mean_mm": 1e3 * max(g["mean_m"] for g in gaps),
                "surface_max_mm": 1e3 * max(g["max_m"] for g in gaps)}
    within = {k: abs(v) <= CRITERIA[k] for k, v in (changes | surfaces).items()}
    return {"counts": {k: [pair[before].get(k), pair[after].get(k)] for k in COUNTS},
            "changes_percent": changes, "surfaces_mm": surfaces, "within": within}


def against_reference(runs: dict[str, dict]) -> dict:
    """Each code's erodible trapezoid against the finest layer resolution (%)."""
    ref = json.loads(REFERENCE.read_text())[REFERENCE_ROW]
    keys = {"runout_m": "runout_m", "duration_s": "duration_s",
            "layer_displaced": "layer_displaced_area_m2",
            "layer_mobilised": "layer_mobilised_area_max_m2"}
    return {tag: {k: 100 * (run[key] / ref[key] - 1) for k, key in keys.items()}
            for tag, run in runs.items()}


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=Path, required=True,
                        help="the folder of collapse_runs.py's tags and comparisons")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/erodible_speed"))
    args = parser.parse_args(argv)
    results: dict = {"criteria": CRITERIA}
    lines = []
    for before, after in (("base", "head"), ("head", "slow")):
        pairs = json.loads((args.runs / f"{before}-vs-{after}.json").read_text())
        results[f"{before}-vs-{after}"] = {name: row(p, before, after)
                                           for name, p in pairs.items()}
        lines += [f"{before} -> {after}", "",
                  "| run | steps | iterations | remeshes | changes (%) | surfaces (mm) |",
                  "|---|---|---|---|---|---|"]
        for name, r in results[f"{before}-vs-{after}"].items():
            c = r["counts"]
            lines.append(
                f"| {name} | {c['steps'][0]} -> {c['steps'][1]} | "
                f"{c['nonlinear_iterations'][0]} -> {c['nonlinear_iterations'][1]} | "
                f"{c['remeshes'][0]} -> {c['remeshes'][1]} | "
                + ", ".join(f"{k} {v:+.2f}" for k, v in r["changes_percent"].items())
                + f" | {r['surfaces_mm']['surface_mean_mm']:.2f} / "
                f"{r['surfaces_mm']['surface_max_mm']:.2f} |")
        lines.append("")
    base = json.loads((args.runs / "base-vs-head.json").read_text())["trapezoid-erodible"]
    results["against_finest_layer"] = against_reference(
        {tag: base[tag] for tag in ("base", "head")})
    lines += ["against the finest layer (%): " + json.dumps(
        {t: {k: round(v, 2) for k, v in d.items()}
         for t, d in results["against_finest_layer"].items()})]
    write_results(args.out, "erodible_speed", results, lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
