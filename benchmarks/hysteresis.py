"""Benchmark: the hysteretic friction (physics/hysteresis.py) on a short, coarse collapse;
convergence in the relaxation time, the mesh and the time step, and the shear rates that
set the default threshold.

Run: python benchmarks/hysteresis.py [--studies threshold tau mesh dt]
         [--out benchmarks/results/hysteresis]

The case: rectangle-rigid (20 x 14 cm, glass beads of the paper, mu_flow = tan 25.5 deg)
with material.friction = "hysteretic" and the defaults (mu_start = tan 27.5 deg,
tau_m = tau_r = 0.02 s, threshold 1 1/s), to t = 0.3 s (the column is then half spread),
mesh.size = 0.02 (about 160 triangles), adaptive steps. Measured: the mobilised fraction
(the mean of s over the mass) at 0.3 s and averaged over [0, 0.3 s], the front X at 0.1,
0.2 and 0.3 s, the mean kinetic energy; and the same run with a constant friction beside
them. Pointwise measures late in the run (the front at 0.3 s) move by a few mm with the
times of the remeshes and depositions, which any change of parameter shifts; the averages
do not.

- threshold: the constant-friction collapse at t = 0.05 ... 0.5 s: the shear rate
  sqrt(2) |Du| of the cells slower than 1 mm/s (their median and 99th percentile) and of
  the faster ones (5th percentile and median);
- tau: tau_m = tau_r = 0.04, 0.02, 0.01, 0.005, 0.0025 s (towards the instantaneous
  switch);
- mesh: mesh.size = 0.04, 0.028, 0.02, 0.014 (the scenario's own), 0.01 at tau = 0.02 s,
  and the same meshes with a constant friction (mesh_constant);
- dt: fixed steps time.dt = 1e-3, 5e-4, 2.5e-4, 1.25e-4 s at mesh.size = 0.02.
Each study's differences are taken to its last (finest) level; the JSON holds every run.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import ngsolve as ngs
import numpy as np
from common.results import read_results, report, write_json

import granflow
from granflow.config import load_config
from granflow.fem.sampling import cell_means
from granflow.scenarios.column import build_column
from granflow.simulation.callbacks import AtTimes, add_callback

T_END = 0.3
BASE = ["mesh.size=0.02", f"time.t_end={T_END}", "time.stop_at_rest=false",
        f"time.output_times=[{T_END}]", "output.progress=false"]
HYSTERETIC = ["material.friction=hysteretic"]
STUDIES = {
    "tau": [[f"material.mobilisation_time={tau}", f"material.rest_time={tau}"]
            for tau in (0.04, 0.02, 0.01, 0.005, 0.0025)],
    "mesh": [[f"mesh.size={h}"] for h in (0.04, 0.028, 0.02, 0.014, 0.01)],
    "mesh_constant": [[f"mesh.size={h}"] for h in (0.04, 0.028, 0.02, 0.014, 0.01)],
    "dt": [[f"time.dt={dt}"] for dt in (1e-3, 5e-4, 2.5e-4, 1.25e-4)],
}
RATE_TIMES = [0.05, 0.1, 0.2, 0.3, 0.4, 0.5]
FRONTS = (0.1, 0.2, T_END)
COMPARED = ["mobilised_fraction_mean", "mobilised_fraction", "kinetic_energy_mean_j",
            *(f"front_x_{x:g}_m" for x in FRONTS)]


def measure(overrides: list[str], out: Path) -> dict:
    """One run to t = 0.3 s: the front at 0.1, 0.2 and 0.3 s, the mobilised fraction at
    0.3 s and averaged over the run, the mean kinetic energy, and the cost."""
    run = granflow.run("rectangle-rigid", [*BASE, *overrides], out=out, force=True,
                       progress=False)
    summary, rows = run.summary, run.diagnostics
    t = rows["t"].to_numpy()

    def mean(column: str) -> float:
        return float(np.trapezoid(rows[column].to_numpy(), t) / t[-1])

    result = {"overrides": overrides, "status": summary.status, "t": float(t[-1]),
              **{f"front_x_{x:g}_m": float(np.interp(x, t, rows["front_x"])) for x in FRONTS},
              "kinetic_energy_mean_j": mean("kinetic_energy"),
              "steps": summary.steps, "nonlinear_iterations": summary.nonlinear_iterations,
              "wall_time_s": summary.wall_time_s, "remeshes": summary.extra.get("remeshes"),
              "n_triangles": summary.extra.get("n_triangles")}
    if "mobilised_fraction" in rows.columns:
        result |= {"mobilised_fraction": float(rows["mobilised_fraction"].iloc[-1]),
                   "mobilised_fraction_mean": mean("mobilised_fraction")}
    report("", result)
    return result


def study(name: str, out: Path) -> dict:
    """The levels of one study and their differences to the last one."""
    friction = [] if name.endswith("_constant") else HYSTERETIC
    runs = [measure([*friction, *level], out / name / f"level{k}")
            for k, level in enumerate(STUDIES[name])]
    finest = runs[-1]
    for run in runs:
        run["differences"] = {key: run[key] - finest[key] for key in COMPARED if key in run}
    return {"levels": runs}


def threshold() -> dict:
    """The shear rates of the constant-friction collapse, slow and flowing cells apart."""
    problem = build_column(load_config("rectangle-rigid", [
        "mesh.size=0.02", f"time.t_end={RATE_TIMES[-1]}", "time.stop_at_rest=false",
        "time.output_times=[]"]))
    rows: list[dict] = []

    def look(sim: object, t: float) -> None:
        rate = math.sqrt(2.0) * cell_means(problem.mesh, problem.solver.strain_rate_norm())[0]
        speed = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))[0]
        slow, fast = rate[speed < 1e-3], rate[speed >= 1e-3]
        rows.append({"t": t, "slow_cells": len(slow), "fast_cells": len(fast),
                     "slow_median": float(np.median(slow)),
                     "slow_q99": float(np.quantile(slow, 0.99)),
                     "fast_q05": float(np.quantile(fast, 0.05)) if len(fast) else None,
                     "fast_median": float(np.median(fast)) if len(fast) else None})
        report("", rows[-1])

    sim = problem.simulation
    add_callback(sim, AtTimes(RATE_TIMES, look), "rates")
    sim.run()
    return {"rows": rows,
            "slow_q99_max": max(r["slow_q99"] for r in rows),
            "fast_median_min": min(r["fast_median"] for r in rows if r["fast_median"])}


def main(argv: list[str]) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--studies", nargs="+", default=["threshold", *STUDIES],
                        choices=["threshold", *STUDIES])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/hysteresis"))
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    path = args.out / "hysteresis.json"
    results = read_results(path)
    if "constant" not in results:
        results["constant"] = measure([], args.out / "runs" / "constant")
        results["hysteretic"] = measure(HYSTERETIC, args.out / "runs" / "hysteretic")
    for name in args.studies:
        results[name] = threshold() if name == "threshold" else study(name, args.out / "runs")
        write_json(path, results)


if __name__ == "__main__":
    main(sys.argv[1:])
