"""Benchmark: convergence and method comparisons of the rigid-bed collapse.

Run: python benchmarks/collapse_study.py VARIANT [VARIANT ...]   (or `all`)
Variants (each runs both shapes; the paper's parameters unless said otherwise):
  fine-mesh    mesh.size halved (about 4x the triangles)
  fine-dt      time.dt_max = 1e-5 (ten times smaller)
  lagrange     mesh velocity (3.7) instead of (3.6)
  no-volfix    (3.6) without the area correction: the raw volume drift of moving vertices
  s52-*        the section 5.2 set-up (dt = 1e-3, tol = 1e-3), cheaper, for the (3.6)/(3.7)
               comparison on the default and the halved mesh
Results: benchmarks/results/collapse/VARIANT.json and one run directory per shape; the
table of all finished variants is printed by benchmarks/collapse_table.py.
"""

from __future__ import annotations

import sys
from pathlib import Path

from common.runs import run_variant

SHAPES = ["trapezoid-rigid", "rectangle-rigid"]
HALF = {"trapezoid-rigid": "mesh.size=0.0105", "rectangle-rigid": "mesh.size=0.007"}
S52 = ["time.dt=1e-3", "numerics.tol=1e-3"]
VARIANTS: dict[str, list[str] | dict[str, list[str]]] = {
    "fine-mesh": {s: [HALF[s]] for s in SHAPES},
    "fine-dt": ["time.dt_max=1e-5"],
    "lagrange": {s: ["numerics.mesh_velocity=\"lagrange\""] for s in SHAPES},
    "no-volfix": ["numerics.volume_correction=false"],
    "s52-elastic": S52,
    "s52-lagrange": [*S52, "numerics.mesh_velocity=\"lagrange\""],
    "s52-elastic-fine": {s: [*S52, HALF[s]] for s in SHAPES},
    "s52-lagrange-fine": {s: [*S52, HALF[s], "numerics.mesh_velocity=\"lagrange\""]
                          for s in SHAPES},
}


def main(names: list[str]) -> None:
    out = Path("benchmarks/results/collapse")
    for name in VARIANTS if names == ["all"] else names:
        spec = VARIANTS[name]
        if isinstance(spec, dict):
            for shape, overrides in spec.items():
                run_variant(f"{name}-{shape}", [shape], overrides, out)
        else:
            run_variant(name, SHAPES, spec, out)


if __name__ == "__main__":
    main(sys.argv[1:] or ["all"])
