"""Benchmark: what following an erodible layer costs a step, located by NGSolve's search
and by the walk through the mesh (``fem/locator.py``), at one state of the default run.

Run: python benchmarks/layer_tracking_cost.py [--at 0.3] [--repeat 20]
         [--out benchmarks/results/layer_tracking_cost]

Runs ``trapezoid-erodible`` to t = AT (no output times), then times, on that state, each
part of a step's tracking both ways (processor time, median of REPEAT):
* the velocity at the layer's line and markers: NGSolve's point search over all the points
  (``fem/sampling.values_at``, its tree rebuilt for the moved vertices, a point outside the
  mesh read at the nearest vertex) against the walk from the triangles of the last step;
* the column's front: the domain less the layer region, eroded, over the whole domain
  against the window behind the last front (``column_layer._column_front``);
* the domain: its boundary segments polygonised against its boundary loop;
* the whole measures of a step, and a whole step of the tracking (``LayerTracking``).
Checks that both ways give the same velocities (to round-off), fronts and areas, and
writes OUT/layer_tracking_cost.json.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import shapely
from common.results import write_results
from common.timing import processor_ms

from granflow.config import load_config
from granflow.fem.sampling import values_at
from granflow.scenarios.column import build_column
from granflow.scenarios.column_layer import _column_front


def whole_domain_front(domain: shapely.Geometry, region: shapely.Geometry,
                       thin: float) -> float:
    """The column front over the whole domain (what the window reproduces)."""
    column = shapely.difference(domain, region).buffer(-0.5 * thin)
    return float(column.bounds[2] + 0.5 * thin) if not column.is_empty else float("nan")


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--at", type=float, default=0.3)
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/layer_tracking_cost"))
    args = parser.parse_args(argv)
    problem = build_column(load_config("trapezoid-erodible", [
        f"time.t_end={args.at!r}", "time.output_times=[]"]))
    problem.simulation.run()
    layer = problem.layer
    assert layer is not None
    mesh, mat, u = layer.current.mesh, layer.material, layer.current.solver.velocity
    layer.sample()                        # the walk starts from the last step's triangles
    locator = layer.locator()
    guess = {name: layer._triangles[name] for name in ("line", "markers")}

    def walked() -> np.ndarray:
        return np.vstack([locator.evaluate(u, pts, *locator.locate(pts, guess[name]))
                          for name, pts in (("line", mat.line), ("markers", mat.markers))])

    def searched() -> np.ndarray:
        return np.vstack([values_at(mesh, u, mat.line), values_at(mesh, u, mat.markers)])

    xy = mesh.ngmesh.Coordinates()
    segments = layer.current.mover.chain.segments

    def polygonised() -> shapely.Geometry:
        edges = shapely.linestrings(xy[segments])
        return shapely.union_all(shapely.get_parts(shapely.polygonize(edges)))

    domain, region, thin = layer.domain(), mat.region(), 0.1 * mat.thickness
    front = layer.measures()["column_front_x"]
    rows = {
        "velocity at the line and markers": (processor_ms(searched, args.repeat),
                                             processor_ms(walked, args.repeat)),
        "column front": (processor_ms(lambda: whole_domain_front(domain, region, thin),
                                      args.repeat),
                         processor_ms(lambda: _column_front(domain, region, thin, front),
                                      args.repeat)),
        "domain": (processor_ms(polygonised, args.repeat), processor_ms(layer.domain, args.repeat)),
    }
    checks = {
        "velocity_max_difference": float(np.abs(walked() - searched()).max()),
        "front_whole_domain_m": whole_domain_front(polygonised(), region, thin),
        "front_window_m": _column_front(domain, region, thin, front),
        "domain_symmetric_difference_m2": float(
            shapely.symmetric_difference(domain, polygonised()).area),
    }
    now = {"measures (all of a step's)": processor_ms(layer.measures, args.repeat),
           "a whole step of the tracking": processor_ms(lambda: layer(problem.simulation), 1)}
    lines = [f"trapezoid-erodible at t = {args.at} s: {mesh.ne} triangles, "
             f"{len(mat.line)} line points, {len(mat.markers)} markers", "",
             "| part of a step | NGSolve's search, whole domain (ms) | walk, window (ms) |",
             "|---|---|---|"]
    lines += [f"| {name} | {a:.2f} | {b:.2f} |" for name, (a, b) in rows.items()]
    lines += [f"| {name} | - | {b:.2f} |" for name, b in now.items()]
    lines += ["", *(f"- {k}: {v:.6g}" for k, v in checks.items())]
    write_results(args.out, "layer_tracking_cost",
                  {"at": args.at, "triangles": mesh.ne, "line_points": len(mat.line),
                   "markers": len(mat.markers), "costs_ms": rows, "now_ms": now,
                   "checks": checks}, lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
