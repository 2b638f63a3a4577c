"""Benchmark: cost of one time step against the mesh size, and peak memory.

Run: python benchmarks/scaling.py [--triangles 300 1200 5000 20000 80000] [--steps 6]
         [--solver auto|umfpack|pardiso] [--out benchmarks/results/scaling]

Each size runs in its own process (so its peak memory is its own): the trapezoid of
section 5 meshed to about N triangles, a few fixed steps of 1e-4 s from rest, each with
exactly one iteration of (3.2) (tol 0.9), so that a step is one nonlinear solve plus the
mesh velocity, the moves and the checks: its wall time (median over the steps), and the
time to assemble, factorise and solve the momentum system (medians of 3). Writes scaling.json, a
table (scaling.md) and a log-log figure (scaling.png) with the fitted growth exponents.
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from common.results import report, write_json, write_markdown

from granflow.io.plots import save_figure
from granflow.simulation.callbacks import add_callback

REFERENCE = (329, 0.021)  # triangles of the trapezoid at mesh.size 0.021 m


def measure(triangles: int, steps: int, solver: str) -> dict:
    """Run in a child process: time the steps of a trapezoid of about ``triangles``."""
    from granflow.config import load_config
    from granflow.scenarios.column import build_column

    size = REFERENCE[1] * math.sqrt(REFERENCE[0] / triangles)
    config = load_config("trapezoid-rigid", [
        f"mesh.size={size!r}", "time.dt=1e-4", f"time.t_end={steps * 1e-4!r}",
        "time.output_times=[]", "numerics.linearization=picard", "time.stop_at_rest=false",
        "numerics.tol=0.9", "time.adaptive=false",
        f"numerics.linear_solver={solver}"])
    build_start = time.perf_counter()
    problem = build_column(config)
    build = time.perf_counter() - build_start
    sim = problem.simulation
    per_step: list[float] = []
    last = [time.perf_counter()]

    def clock(_: object) -> None:
        now = time.perf_counter()
        per_step.append(now - last[0])
        last[0] = now

    add_callback(sim, clock, "clock")
    last[0] = time.perf_counter()
    sim.run()
    system = problem.solver.nonlinear.picard_system
    x = problem.solver.solution.vec
    out = x.CreateVector()
    timings: dict[str, list[float]] = {"assemble": [], "factorise": [], "solve": []}
    for _ in range(3):
        t0 = time.perf_counter()
        system.a.Assemble()
        t1 = time.perf_counter()
        system.lu.update()
        t2 = time.perf_counter()
        system.lu.solve(system.f.vec, out)
        t3 = time.perf_counter()
        for key, value in zip(timings, (t1 - t0, t2 - t1, t3 - t2), strict=True):
            timings[key].append(value)
    return {
        "target_triangles": triangles, "mesh_size_m": size, "n_triangles": problem.mesh.ne,
        "n_dofs": problem.solver.space.ndof, "build_s": build,
        "step_s": statistics.median(per_step[1:] or per_step),
        "iterations": sim.nonlinear_iterations, "steps": sim.step,
        **{f"{k}_s": statistics.median(v) for k, v in timings.items()},
        "peak_rss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2,
        "solver": problem.solver.nonlinear.picard_system.lu._solver,
    }


def slope(rows: list[dict], key: str, lo: int, hi: int) -> float | None:
    pts = [(r["n_triangles"], r[key]) for r in rows if lo <= r["n_triangles"] <= hi]
    if len(pts) < 2:
        return None
    (n0, c0), (n1, c1) = pts[0], pts[-1]
    return math.log(c1 / c0) / math.log(n1 / n0)


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--triangles", nargs="+", type=int,
                        default=[300, 1200, 5000, 20000, 80000])
    parser.add_argument("--steps", type=int, default=6)
    parser.add_argument("--solver", default="auto")
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/scaling"))
    parser.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        print(json.dumps(measure(args.child, args.steps, args.solver)))
        return
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    for n in args.triangles:
        done = subprocess.run([sys.executable, __file__, "--child", str(n), "--steps",
                               str(args.steps), "--solver", args.solver],
                              capture_output=True, text=True, check=True)
        rows.append(json.loads(done.stdout.strip().splitlines()[-1]))
        report("", rows[-1])
    fits = {key: {"up_to_20k": slope(rows, key, 0, 25000),
                  "20k_to_80k": slope(rows, key, 15000, 10**9)}
            for key in ("step_s", "factorise_s", "assemble_s", "solve_s")}
    write_json(args.out / f"scaling-{rows[0]['solver']}.json",
               {"rows": rows, "growth_exponents": fits})
    lines = ["| triangles | dofs | step (s) | assemble (s) | factorise (s) | solve (s) | "
             "peak memory (GB) |", "|---|---|---|---|---|---|---|"]
    lines += [f"| {r['n_triangles']} | {r['n_dofs']} | {r['step_s']:.4g} | "
              f"{r['assemble_s']:.3g} | {r['factorise_s']:.3g} | {r['solve_s']:.3g} | "
              f"{r['peak_rss_gb']:.2f} |" for r in rows]
    lines.append("")
    lines.append("growth exponents (cost ~ n^k): " + json.dumps(fits))
    write_markdown(args.out / f"scaling-{rows[0]['solver']}.md", lines, show=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    n = [r["n_triangles"] for r in rows]
    for key, label in (("step_s", "one time step"), ("factorise_s", "factorisation"),
                       ("assemble_s", "assembly"), ("solve_s", "back-substitution")):
        ax.loglog(n, [r[key] for r in rows], "o-", label=label)
    ax.loglog(n, [rows[0]["step_s"] * (x / n[0]) for x in n], "k:", label="n^1")
    ax.set_xlabel("triangles")
    ax.set_ylabel("wall time (s)")
    ax.set_title(f"Trapezoid, one core, {rows[0]['solver']}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, args.out / f"scaling-{rows[0]['solver']}.png", dpi=120)


if __name__ == "__main__":
    main(sys.argv[1:])
