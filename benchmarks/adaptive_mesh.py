"""Benchmark: the adaptive mesh (``mesh.adaptive``) against the uniform one, on the verified
collapses, and the erodible trapezoid against the finest layer resolution.

Run: python benchmarks/adaptive_mesh.py [--scenarios trapezoid-erodible cylinder-erodible]
         [--variants uniform adaptive ...] [--set key=value ...]
         [--out benchmarks/results/adaptive_mesh]

Each variant (``VARIANTS``: its overrides) of each scenario runs to rest into
OUT/runs/VARIANT/SCENARIO (kept when finished, continued from a checkpoint; a run made by
an earlier checkout can be put there). For each scenario, every variant is compared with
the first (``uniform``: the earlier defaults, the uniform mesh and the tension scaled with
mesh.size; ``adaptive`` is the defaults): free surfaces at the output times (mean / max
distance), runout, the rest rule's stop time, the flow's duration (below 1 % flowing), the
layer's displaced and largest mobilised areas; and the erodible trapezoid with the finest
layer resolution of ``erosion_layers.py`` (8 isotropic cells across, its JSON) against the
accuracy the defaults must keep (``ACCURACY``: runout 1 %, duration 2 %, displaced 2 %,
largest mobilised 5 %).
Writes OUT/adaptive_mesh.json and OUT/adaptive_mesh.md.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from common.results import report, write_json, write_markdown
from common.runs import COLLAPSE_KEYS, flow_duration, run_or_continue, surfaces_m

VARIANTS = {"uniform": ["mesh.adaptive=false", "surface_tension.length=mesh_size"],
            "adaptive": [],
            # the adaptive mesh with the earlier tension, and with the bulk coarser at rest
            "adaptive-mesh-size": ["surface_tension.length=mesh_size"],
            "rest-coarsening-2": ["surface_tension.length=mesh_size", "mesh.rest_coarsening=2"]}
KEYS = [*COLLAPSE_KEYS, "layer_displaced_area_m2", "layer_mobilised_area_max_m2",
        "erosion_depth_max_m", "surface_tension_steps", "adaptive_refits"]
COMPARED = ["runout_m", "stop_time_s", "duration_s", "layer_displaced_area_m2",
            "layer_mobilised_area_max_m2"]
ACCURACY = {"runout_m": 0.01, "duration_s": 0.02, "layer_displaced_area_m2": 0.02,
            "layer_mobilised_area_max_m2": 0.05}     # relative, against the finest layer
REFERENCE = Path(__file__).parent / "results/erosion_layers/erosion_layers.json"
REFERENCE_ROW = "slope0-cells8"        # trapezoid-erodible, 8 isotropic cells across


def relative(row: dict, base: dict, key: str) -> float | None:
    a, b = row.get(key), base.get(key)
    return None if a is None or not b else a / b - 1


def compare(rows: dict[str, dict], runs: dict[str, Path]) -> dict[str, dict]:
    """Every variant against the first: relative changes and the free surfaces (mm)."""
    names = list(rows)
    first = names[0]
    out = {}
    for name in names[1:]:
        out[name] = {key: relative(rows[name], rows[first], key) for key in COMPARED}
        out[name]["surfaces_mm"] = {t: [round(1e3 * d["mean_m"], 2), round(1e3 * d["max_m"], 2)]
                                    for t, d in surfaces_m(runs[first], runs[name]).items()}
    return out


def against_reference(rows: dict[str, dict]) -> dict[str, dict]:
    """The erodible trapezoid's variants against the finest layer resolution."""
    reference = json.loads(REFERENCE.read_text())[REFERENCE_ROW]
    out = {}
    for name, row in rows.items():
        change = {key: relative(row, reference, key) for key in ACCURACY}
        out[name] = change | {"within": all(v is not None and abs(v) <= ACCURACY[k]
                                            for k, v in change.items())}
    return out


def table(results: dict) -> str:
    lines = ["| scenario | variant | triangles (end) | steps | iterations | remeshes | stop (s) "
             "| runout (m) | duration (s) | displaced (m²) | wall time (s) |",
             "|" + "---|" * 11]
    for scenario, by_variant in results["runs"].items():
        for name, r in by_variant.items():
            cells = [r.get("n_triangles"), r.get("steps"), r.get("nonlinear_iterations"),
                     r.get("remeshes")]
            figures = [f"{r[k]:.4f}" if r.get(k) is not None else "-" for k in
                       ("stop_time_s", "runout_m", "duration_s")]
            displaced = r.get("layer_displaced_area_m2")
            lines.append(f"| {scenario} | {name} | {' | '.join(map(str, cells))} | "
                         f"{' | '.join(figures)} | "
                         f"{'-' if displaced is None else f'{displaced:.3e}'} | "
                         f"{r.get('wall_time_s', 0):.0f} |")
    lines += ["", "| scenario | variant against the first | runout | stop | duration | "
              "displaced | mobilised | free surfaces, worst mean / max (mm) |",
              "|---|---|---|---|---|---|---|---|"]
    for scenario, by_variant in results["changes"].items():
        for name, c in by_variant.items():
            pct = [f"{100 * c[k]:+.2f} %" if c.get(k) is not None else "-" for k in COMPARED]
            worst = [max((d[i] for d in c["surfaces_mm"].values()), default=float("nan"))
                     for i in (0, 1)]
            lines.append(f"| {scenario} | {name} | {' | '.join(pct)} | "
                         f"{worst[0]:.2f} / {worst[1]:.2f} |")
    if "reference" in results:
        lines += ["", "| trapezoid-erodible against 8 isotropic cells | runout | duration | "
                  "displaced | mobilised | within |", "|---|---|---|---|---|---|"]
        for name, c in results["reference"].items():
            pct = [f"{100 * c[k]:+.2f} %" if c.get(k) is not None else "-" for k in ACCURACY]
            lines.append(f"| {name} | {' | '.join(pct)} | {'yes' if c['within'] else 'no'} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenarios", nargs="+",
                        default=["trapezoid-erodible", "cylinder-erodible"])
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS),
                        help="names in VARIANTS, or NAME=key=value;key=value")
    parser.add_argument("--set", nargs="*", default=[], help="overrides of every run")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/adaptive_mesh"))
    args = parser.parse_args()
    variants = {}
    for v in args.variants:
        name, _, sets = v.partition("=")
        variants[name] = VARIANTS[name] if not sets else sets.split(";")
    results: dict = {"variants": variants, "set": args.set, "runs": {}, "changes": {}}
    for scenario in args.scenarios:
        rows, runs = {}, {}
        for name, sets in variants.items():
            runs[name] = args.out / "runs" / name / scenario
            summary = run_or_continue(scenario, [*sets, *args.set], runs[name])
            rows[name] = {k: summary.get(k) for k in KEYS} | {
                "duration_s": flow_duration(runs[name])}
            report(f"{scenario} {name}", rows[name])
        results["runs"][scenario] = rows
        results["changes"][scenario] = compare(rows, runs)
        if scenario == "trapezoid-erodible" and not args.set:
            results["reference"] = against_reference(rows)
        write_json(args.out / "adaptive_mesh.json", results)
    write_markdown(args.out / "adaptive_mesh.md", table(results), show=True)


if __name__ == "__main__":
    main()
