"""Benchmark: where and when the nonlinear iteration (3.2) spends its iterations.

Run: python benchmarks/iteration_anatomy.py [SCENARIO] [--set key=value ...]
         [--window N] [--out benchmarks/results/iteration_anatomy/NAME.json]

Runs SCENARIO (default: trapezoid-erodible) without its file outputs and records, for every
fixed-point iteration, the relative change and where it sits: the share of the change's
squared L2 norm inside the erodible layer (z below its top) and the centroid of the
triangle with the largest change. Every accepted step is labelled by the events just before
it: a remesh, a switch of the numerical surface tension (3.8)-(3.11) on or off, or none,
and the iterations are summed by label over the WINDOW steps after each event. It prints
that table and writes the per-step and per-iteration records as JSON.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections import Counter
from collections.abc import Callable
from pathlib import Path

import ngsolve as ngs
import numpy as np
from common.results import write_json

from granflow.config import load_config
from granflow.fem import nonlinear
from granflow.runner import build_problem
from granflow.simulation.callbacks import add_callback


class Probe:
    """Records each fixed-point iteration's change through ``FixedPointSystem.iterate``."""

    def __init__(self, layer_top: float, velocity_floor: float) -> None:
        self.layer_top, self.velocity_floor = layer_top, velocity_floor
        self.iterations: list[dict] = []
        self.dump: Callable[[], None] = lambda: None   # called every 200 iterations
        self.step = 0
        original = nonlinear.FixedPointSystem.iterate
        probe = self

        def iterate(system: nonlinear.FixedPointSystem, out: ngs.BaseVector,
                    corrected: bool = False) -> None:
            original(system, out, corrected)
            probe.record(system, out, corrected)

        nonlinear.FixedPointSystem.iterate = iterate   # type: ignore[method-assign]

    def record(self, system: nonlinear.FixedPointSystem, out: ngs.BaseVector,
               corrected: bool) -> None:
        state = system.probe_state                     # set by the patched solver below
        delta = ngs.GridFunction(state.space)
        delta.vec.data = out - state.vec
        du = delta.components[0]
        mesh = state.space.mesh
        per_cell = ngs.Integrate(du * du * ngs.dx, mesh, element_wise=True).NumPy()
        total = float(per_cell.sum())
        xy = mesh.ngmesh.Coordinates()
        tri = mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1
        centroid = xy[tri].mean(axis=1)
        in_layer = centroid[:, 1] < self.layer_top
        worst = int(np.argmax(per_cell))
        u = state.components[0]
        norm = float(np.sqrt(ngs.Integrate(u * u * ngs.dx, mesh)))
        floor = self.velocity_floor * float(np.sqrt(ngs.Integrate(ngs.CF(1.0), mesh)))
        self.iterations.append({
            "step": self.step, "corrected": corrected,
            "change": float(np.sqrt(total)) / max(norm, floor),
            "layer_share": float(per_cell[in_layer].sum() / total) if total > 0 else 0.0,
            "worst_x": float(centroid[worst, 0]), "worst_z": float(centroid[worst, 1])})
        if len(self.iterations) % 200 == 0:
            self.dump()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenario", nargs="?", default="trapezoid-erodible")
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--window", type=int, default=8,
                        help="steps after an event that are counted as its cost")
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/iteration_anatomy/anatomy.json"))
    args = parser.parse_args()
    config = load_config(args.scenario, [*args.overrides, "output.progress=false"])
    layer_top = config.geometry.erodible_thickness if config.geometry.kind == "column" else 0
    probe = Probe(layer_top, config.numerics.velocity_floor)
    original_init = nonlinear.NonlinearSolver.__init__

    def init(self: nonlinear.NonlinearSolver, picard: nonlinear.FixedPointSystem,
             *rest: object, **kw: object) -> None:
        original_init(self, picard, *rest, **kw)   # type: ignore[arg-type]
        picard.probe_state = self.state            # type: ignore[attr-defined]

    nonlinear.NonlinearSolver.__init__ = init      # type: ignore[method-assign]
    problem = build_problem(config)
    sim = problem.simulation
    steps: list[dict] = []
    last: dict = {"remeshes": 0, "tension": False, "gamma": None, "fraction": None}

    def observe(s: object) -> None:
        tension = problem.mover.tension
        on = bool(tension is not None and tension.state.active)
        remeshes = getattr(problem, "remesher", None)
        count = remeshes.remeshes if remeshes is not None else 0
        events = []
        if count != last["remeshes"]:
            events.append("remesh")
        if on != last["tension"]:
            events.append("tension on" if on else "tension off")
        gamma = problem.solver.surface_tension.vec.FV().NumPy().copy()
        before = last["gamma"]
        jump = (float(np.abs(gamma - before).max()) if before is not None
                and len(before) == len(gamma) and "remesh" not in events else None)
        share = getattr(getattr(problem, "current", None), "fraction", None)
        fraction = share.vec.FV().NumPy().copy() if share is not None else None
        shift = (float(np.abs(fraction - last["fraction"]).max()) if fraction is not None
                 and last["fraction"] is not None and len(fraction) == len(last["fraction"])
                 and "remesh" not in events else None)
        last.update(remeshes=count, tension=on, gamma=gamma, fraction=fraction)
        report = sim.last_report
        steps.append({"step": sim.step, "t": sim.t, "dt": sim.dt,
                      "iterations": report.iterations if report else 0, "events": events,
                      "tension": on, "rejected_so_far": sim.rejected_steps,
                      "gamma_max": float(np.abs(gamma).max()), "gamma_jump": jump,
                      "fraction_jump": shift})
        probe.step = sim.step

    probe.dump = lambda: write(args.out, {"partial": True, "steps_record": steps,
                                          "iterations_record": probe.iterations})

    add_callback(sim, observe, "anatomy")
    start = time.perf_counter()
    result = sim.run()
    wall = time.perf_counter() - start
    label = ["" for _ in steps]          # the latest event within the window before a step
    for k, row in enumerate(steps):
        for event in row["events"]:
            for j in range(k, min(k + args.window, len(steps))):
                label[j] = label[j] or event
    cost: Counter[str] = Counter()
    count: Counter[str] = Counter()
    for row, lab in zip(steps, label, strict=True):
        key = lab or "quiet"
        cost[key] += row["iterations"]
        count[key] += 1
    total = sum(cost.values())
    print(f"{args.scenario} {' '.join(args.overrides)}: {result.status} at t = {result.t_final:.4g}"
          f" s, {result.steps} steps, {result.nonlinear_iterations} iterations (with rejected "
          f"steps), {result.rejected_steps} rejected {result.rejections}, wall {wall:.1f} s")
    print(f"{'steps after':14s} {'steps':>6s} {'iterations':>10s} {'per step':>9s} {'share':>6s}")
    for key in sorted(cost, key=cost.__getitem__, reverse=True):
        print(f"{key:14s} {count[key]:6d} {cost[key]:10d} {cost[key] / count[key]:9.2f} "
              f"{cost[key] / total:6.1%}")
    heavy = [it for it in probe.iterations if it["change"] > 0]
    shares = [it["layer_share"] for it in heavy]
    if shares and layer_top > 0:
        print(f"share of the iterations' change inside the layer: median "
              f"{statistics.median(shares):.2f}; iterations whose change is mostly in the "
              f"layer: {sum(s > 0.5 for s in shares) / len(shares):.1%}")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    write(args.out, {
        "scenario": args.scenario, "overrides": args.overrides, "status": result.status,
        "t_final": result.t_final, "steps": result.steps,
        "nonlinear_iterations": result.nonlinear_iterations,
        "rejected_steps": result.rejected_steps, "rejections": result.rejections,
        "wall_time_s": wall, "window": args.window,
        "by_event": {k: {"steps": count[k], "iterations": cost[k]} for k in cost},
        "steps_record": steps, "iterations_record": probe.iterations})


def write(out: Path, result: dict) -> None:
    """The record as JSON (also called while the run goes on, every 50 steps)."""
    write_json(out, result, indent=1)


if __name__ == "__main__":
    main()
