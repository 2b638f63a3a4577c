"""Benchmark: an erodible layer meshed only ahead of the flow (``mesh.layer_ahead``) against
the whole layer meshed from the start, side by side, on the slope study's most expensive
kind of run: the rectangle on a 22-degree slope over a 5 mm layer of 3.21 m (1.3 times the
rigid runout), mu(I), 2 cells across the layer, to t = 0.3 s by default.

Run: python benchmarks/layer_ahead.py [--ahead 0 0.1 0.2] [--t-end 0.3] [--set key=value]
         [--out benchmarks/results/layer_ahead]

Each run goes to OUT/runs/ahead-A (A = 0 is the whole layer). The table gives the wall
time and its ratio to the whole layer's, the triangles at the end, the steps, nonlinear
iterations and remeshes, and what the flow did: the front, the column's front, the layer
material displaced, and the mean and largest distance of the free surface and of the
layer's top (the tracked material line) from the whole layer's run at each output time.
The layer beyond the meshed end is at rest behind a frictionless wall, which holds an
undisturbed layer exactly; what moves the results is that the lengthened mesh is another
mesh, so the differences are to be read against the mesh's own (the layer convergence study,
``erosion_layers.py``). OUT/layer_ahead.json holds the figures, OUT/layer_ahead.md the table.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from common.results import report, write_json, write_markdown
from common.runs import distances_mm, run_summary

from granflow.io.run_dir import RunDir

CASE = ["boundary.normal_load=reaction", "numerics.mesh_velocity=elastic",
        "surface_tension.enabled=true", "mesh.layer_cells=2", "material.rheology=mu-i",
        "geometry.erodible_thickness=0.005", "geometry.height=0.145",
        "geometry.slope_deg=22.0", "geometry.bed_length=3.21"]
KEYS = ["wall_time_s", "n_triangles", "steps", "nonlinear_iterations", "remeshes",
        "runout_m", "column_front_m", "layer_displaced_area_m2", "layer_area_drift_max",
        "layer_lengthenings", "layer_meshed_end_m", "volume_relative_error"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ahead", type=float, nargs="+", default=[0.0, 0.1, 0.2])
    parser.add_argument("--t-end", type=float, default=0.3)
    parser.add_argument("--set", action="append", default=[], dest="sets")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/layer_ahead"))
    args = parser.parse_args()
    times = [round(args.t_end * k / 3, 6) for k in (1, 2, 3)]
    common = [*CASE, f"time.t_end={args.t_end!r}", f"time.output_times={times!r}",
              "time.stop_at_rest=false", *args.sets]
    results: dict[str, dict] = {}
    roots = {}
    for ahead in args.ahead:
        name = f"ahead-{ahead:g}"
        roots[name] = args.out / "runs" / name
        summary = run_summary("rectangle-rigid", [*common, f"mesh.layer_ahead={ahead!r}"],
                              roots[name])
        results[name] = {k: RunDir.summary(roots[name]).get(k) for k in KEYS} | {
            "status": summary["status"], "overrides": [*common, f"mesh.layer_ahead={ahead!r}"]}
        report(name, results[name])
    reference = f"ahead-{args.ahead[0]:g}"
    for name, r in results.items():
        r["time_ratio"] = r["wall_time_s"] / results[reference]["wall_time_s"]
        if name != reference:
            r["free_surface_mm"] = distances_mm(roots[reference], roots[name], "free_surface",
                                                 common_extent=True)
            r["layer_line_mm"] = distances_mm(roots[reference], roots[name], "layer_line",
                                               common_extent=True)
    write_json(args.out / "layer_ahead.json", results)
    lines = [f"Rectangle on 22 deg over a 5 mm layer (mu(I), 2 cells), to t = {args.t_end} s; "
             f"distances from `{reference}` at t = {', '.join(map(str, times))} s "
             "(mean / largest, mm).", "",
             "| run | wall time (s) | ratio | triangles | steps | iterations | remeshes | "
             "lengthenings | meshed end (m) | front (m) | column front (m) | "
             "displaced layer (m^2) | free surface (mm) | layer top (mm) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        surface = "; ".join(f"{a} / {b}" for a, b in r.get("free_surface_mm", {}).values())
        line = "; ".join(f"{a} / {b}" for a, b in r.get("layer_line_mm", {}).values())
        lines.append(
            f"| {name} | {r['wall_time_s']:.0f} | {r['time_ratio']:.2f} | {r['n_triangles']} | "
            f"{r['steps']} | {r['nonlinear_iterations']} | {r['remeshes']} | "
            f"{r.get('layer_lengthenings') or 0} | "
            f"{r.get('layer_meshed_end_m') or 3.21:.3f} | {r['runout_m']:.4f} | "
            f"{r['column_front_m']:.4f} | {r['layer_displaced_area_m2']:.3e} | "
            f"{surface or '-'} | {line or '-'} |")
    write_markdown(args.out / "layer_ahead.md", lines, show=True)


if __name__ == "__main__":
    main()
