"""Benchmark: the boundary checks of a move on long erodible layers.

Run: python benchmarks/fold_checks.py [--out benchmarks/results/fold_checks]

`segments_intersect` (is the boundary polygon still simple after a move?) runs at every
attempted step. Testing all n^2 / 2 pairs of segments, on the 22-deg rectangle
over its 3.2 m layer (2,500 boundary segments) took 45 % of the run's time (py-spy);
granflow prunes the pairs with a k-d tree. This script times both on the initial meshes
of the default erodible trapezoid and of the 22-deg rectangle over the layer (the
configuration of benchmarks/slopes.py), checks that they agree, and writes
OUT/fold_checks.json.

Also the clamping of a remesh's field transfer (`ale/transfer.py: clamp_inside`): every
vertex and edge midpoint of the mesh lifted by 0.5 mm (so the surface's points lie
outside) clamped back into the mesh, a point-by-point search over all segments
against granflow's vectorised, k-d-tree-pruned one (which took 21 % of the 22-deg
trapezoid's run over its 5.85 m layer before; py-spy). Both must give the same points.
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from common.results import report, write_json

from granflow.ale.free_surface import BoundaryChain, pairs_cross, segments_intersect
from granflow.ale.transfer import _edge_midpoints, clamp_all_pairs, clamp_inside
from granflow.config import load_config
from granflow.scenarios.column import build_column

SLOPES = ["boundary.normal_load=reaction", "geometry.slope_deg=22.0",
          "geometry.erodible_thickness=0.005", "numerics.mesh_velocity=elastic",
          "surface_tension.enabled=true", "mesh.layer_cells=2", "geometry.height=0.145",
          "geometry.bed_length=3.2199018856466766"]
CASES = {"trapezoid-erodible": ("trapezoid-erodible", []),
         "rectangle-erodible-22": ("rectangle-rigid", SLOPES)}


def pairwise(xy: np.ndarray, segments: np.ndarray) -> bool:
    """The unpruned test: the same predicate on every pair of segments."""
    i, j = np.triu_indices(len(segments), k=1)
    return pairs_cross(xy, segments, i, j)


def clamping(mesh) -> dict:
    """Both clampings of the lifted vertices and edge midpoints: agreement and times."""
    points = np.vstack([mesh.ngmesh.Coordinates(), _edge_midpoints(mesh)[0]]) + [0.0, 5e-4]
    start = time.perf_counter()
    old = clamp_all_pairs(mesh, points)
    middle = time.perf_counter()
    new = clamp_inside(mesh, points)
    end = time.perf_counter()
    if not np.array_equal(old, new):
        raise SystemExit("the two clampings disagree")
    return {"points": len(points), "outside": int(np.count_nonzero((new != points).any(1))),
            "all_pairs_s": middle - start, "pruned_s": end - middle,
            "ratio": (middle - start) / (end - middle)}


def timed(check, xy: np.ndarray, segments: np.ndarray, repeat: int = 5) -> tuple[bool, float]:
    times, answer = [], False
    for _ in range(repeat):
        start = time.perf_counter()
        answer = check(xy, segments)
        times.append(time.perf_counter() - start)
    return answer, statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/fold_checks"))
    args = parser.parse_args()
    results = {}
    for name, (scenario, overrides) in CASES.items():
        mesh = build_column(load_config(scenario, overrides)).mesh
        xy, segments = mesh.ngmesh.Coordinates().copy(), BoundaryChain(mesh).segments
        folded = xy.copy()             # the column's highest node pushed through the bed
        folded[np.argmax(xy[:, 1]), 1] = -0.05
        row = {"triangles": mesh.ne, "boundary_segments": len(segments)}
        for label, polygon in (("as_meshed", xy), ("folded", folded)):
            old, t_old = timed(pairwise, polygon, segments)
            new, t_new = timed(segments_intersect, polygon, segments)
            if old != new:
                raise SystemExit(f"{name} {label}: the two tests disagree ({old} vs {new})")
            row[label] = {"intersects": new, "pairwise_s": t_old, "pruned_s": t_new,
                          "ratio": t_old / t_new}
        row["clamp"] = clamping(mesh)
        results[name] = row
        report(name, row)
    write_json(args.out / "fold_checks.json", results)


if __name__ == "__main__":
    main()
