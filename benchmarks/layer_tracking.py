"""Benchmark: what the tracking of an erodible layer's material loses, and what a strong
layer keeps, on a coarse, short collapse (a 1 cm layer, 4 cm cells, 0.1 s).

Run: python benchmarks/layer_tracking.py [--out benchmarks/results/layer_tracking]

1. Conservation: a 20-degree column over a layer of its own material, the flow digging
   through the whole layer; the layer material inside the domain at 0.1 s against its
   initial area (``layer_area_drift``) with 2 and 4 cells across the layer and with a time
   step four times smaller. A drift that falls with the cells and not with the step is a
   discretisation error of the flow (Taylor-Hood velocities are divergence-free only
   weakly), not of the tracking.
2. Two materials: the same column over a 60-degree layer, against the layer of its own
   (20-degree) material: the layer material displaced by more than one grain diameter.
OUT/layer_tracking.json holds every run's measures, OUT/layer_tracking.md the tables.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from common.results import report, write_results

from granflow.config import load_config
from granflow.scenarios.column import build_column

BASE = ["mesh.size=0.04", "geometry.erodible_thickness=0.01", "mesh.layer_cells=2",
        "geometry.bed_length=0.5", "time.output_times=[]", "surface_tension.enabled=false",
        "time.stop_at_rest=false", "time.t_end=0.1", "material.friction_angle_deg=20",
        "boundary.bed_friction_deg=20"]
CASES = {
    "conservation, 2 cells": [],
    "conservation, 4 cells": ["mesh.layer_cells=4"],
    "conservation, 2 cells, dt / 4": ["time.dt_max=2.5e-4"],
    "layer of 60 degrees": ["layer.friction_angle_deg=60"],
}


def measure(overrides: list[str]) -> dict:
    problem = build_column(load_config("trapezoid-erodible", [*BASE, *overrides]))
    start = time.perf_counter()
    problem.simulation.run()
    assert problem.layer is not None
    return problem.layer.measures() | {"steps": problem.simulation.step,
                                       "triangles": problem.mesh.ne,
                                       "seconds": time.perf_counter() - start}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/layer_tracking"))
    args = parser.parse_args()
    results = {}
    for name, overrides in CASES.items():
        results[name] = measure(overrides) | {"overrides": overrides}
        report(name, results[name])
    lines = ["| case | triangles | steps | layer area drift | displaced layer (m^2) | "
             "erosion depth (mm) | column front (m) |", "|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        lines.append(f"| {name} | {r['triangles']} | {r['steps']} | "
                     f"{r['layer_area_drift']:+.2e} | {r['layer_displaced_area']:.3g} | "
                     f"{1e3 * r['erosion_depth_max']:.1f} | {r['column_front_x']:.4f} |")
    write_results(args.out, "layer_tracking", results, lines, show=True)


if __name__ == "__main__":
    main()
