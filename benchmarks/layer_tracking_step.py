"""Benchmark: one step of the erodible layer's tracking, part by part, on states of the
default run, for this checkout and an earlier one.

Run: python benchmarks/layer_tracking_step.py [--at 0.3 0.6] [--repeat 40] [--tag NAME]
         [--out benchmarks/results/layer_tracking_step]
     PYTHONPATH=OLD/src python benchmarks/layer_tracking_step.py --tag before

Runs ``trapezoid-erodible`` (no output times) to each time AT, then times on that state,
in processor time (median of REPEAT calls), what ``LayerTracking`` does after an accepted
step: ``sample`` (the line and markers located, the velocity and its rate read there),
``measures`` (the diagnostics row's entrainment columns) and ``LayerMaterial.advance`` (the
line and markers moved, the line refined, untangled and coarsened; on a copy). Writes
OUT/TAG.json and OUT/layer_tracking_step.md comparing every tag
recorded there.
"""

from __future__ import annotations

import argparse
import copy
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from common.results import read_results, write_json, write_markdown

from granflow.config import load_config
from granflow.scenarios.column import build_column

PARTS = ("sample", "measures", "advance")


def cost(f: Callable[[], object], repeat: int) -> float:
    """Processor time of one call (ms), median of ``repeat``."""
    times = []
    for _ in range(repeat):
        start = time.process_time()
        f()
        times.append(time.process_time() - start)
    return 1e3 * float(np.median(times))


def parts_at(at: float, repeat: int) -> dict:
    """The parts' costs on the state of the default run at t = ``at``."""
    problem = build_column(load_config("trapezoid-erodible", [
        f"time.t_end={at!r}", "time.output_times=[]"]))
    problem.simulation.run()
    layer = problem.layer
    assert layer is not None
    layer.measures()                      # the column front's window, as after a step
    mat, dt = layer.material, problem.simulation.dt
    lines, markers = layer.line_velocity, layer.marker_velocity
    costs = {"sample": cost(layer.sample, repeat), "measures": cost(layer.measures, repeat),
             "advance": cost(lambda: copy.deepcopy(mat).advance(lines, markers, dt), repeat)
             - cost(lambda: copy.deepcopy(mat), repeat)}
    return {"t": problem.simulation.t, "triangles": problem.mesh.ne,
            "line_points": len(mat.line), "markers": len(mat.markers), "costs_ms": costs,
            "step_ms": sum(costs.values())}


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--at", type=float, nargs="+", default=[0.3, 0.6])
    parser.add_argument("--repeat", type=int, default=40)
    parser.add_argument("--tag", default="now")
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/layer_tracking_step"))
    args = parser.parse_args(argv)
    states = {f"{at:g}": parts_at(at, args.repeat) for at in args.at}
    write_json(args.out / f"{args.tag}.json", {"repeat": args.repeat, "states": states})
    lines = ["| code | t (s) | triangles | line points | markers | "
             + " | ".join(f"{p} (ms)" for p in PARTS) + " | a step (ms) |",
             "|---|---|---|---|---|" + "---|" * (len(PARTS) + 1)]
    for tagged in sorted(args.out.glob("*.json")):
        record = read_results(tagged)
        for at, s in record.get("states", {}).items():
            lines.append(f"| {tagged.stem} | {at} | {s['triangles']} | {s['line_points']} | "
                         f"{s['markers']} | "
                         + " | ".join(f"{s['costs_ms'][p]:.2f}" for p in PARTS)
                         + f" | {s['step_ms']:.2f} |")
    write_markdown(args.out / "layer_tracking_step.md", lines, show=True)


if __name__ == "__main__":
    main(sys.argv[1:])
