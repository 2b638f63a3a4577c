"""Benchmark: how a run depends on the code path of Intel MKL (PARDISO) and what the
reproducible path costs.

Run: python benchmarks/reproducibility.py [--settings COMPATIBLE AUTO AVX2 AVX512 umfpack]
         [--sizes 0.02 0.005] [--out benchmarks/results/reproducibility]

Each setting runs in a fresh process (MKL reads ``MKL_CBWR`` when it first computes):
``COMPATIBLE`` (granflow's default: SSE2 kernels, the same on every x86-64 CPU), ``AUTO``
(this CPU's own kernels, reproducible on this machine only), ``AVX2`` or ``AVX512`` (those
kernels on any CPU that has them), ``default`` (``MKL_CBWR`` empty: MKL's choice outside
its reproducible mode) and ``umfpack`` (NGSolve's UMFPACK instead of PARDISO). Per setting: the
default collapse to rest (steps, iterations, stop time, runout); the column held by a
60-degree friction at the scenario's velocity floor (1 mm/s) and at the creep scale
(1e-7 m/s; tests/verification/test_axisymmetric_column.py); the erosion fronts of the
whole layer and of the layer meshed ahead of the flow (tests/verification/test_erodible.py);
and the CPU time of PARDISO's
numeric refactorisation of the first step's matrix at each mesh size (median of five).
Prints a table and writes OUT/reproducibility.json with the machine's CPU and packages.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from importlib import metadata
from pathlib import Path

from common.results import write_json

REST = ["mesh.size=0.02", "time.output_times=[0.05]", "time.t_end=0.05",
        "material.friction_angle_deg=60", "boundary.bed_friction_deg=60",
        "time.stop_at_rest=false", "numerics.linearization=newton",
        "numerics.max_iterations=50"]
ERODIBLE = ["mesh.size=0.04", "geometry.erodible_thickness=0.01", "mesh.layer_cells=2",
            "mesh.layer_aspect=1", "numerics.tol=3e-5", "numerics.anderson_depth=0",
            "geometry.bed_length=0.9", "time.output_times=[]", "surface_tension.enabled=false",
            "time.stop_at_rest=false", "time.t_end=0.15", "material.friction_angle_deg=20",
            "boundary.bed_friction_deg=20", "geometry.slope_deg=10"]
PACKAGES = ("mkl", "ngsolve", "numpy", "scipy", "intel-openmp")

CHILD = r'''
import json, sys, time
import ngsolve as ngs
import numpy as np
from pyngcore import Flags
from granflow.config import load_config
from granflow.fem.linalg import PARDISO_FLAGS
from granflow.fem.sampling import cell_means
from granflow.runner import build_problem

solver, sizes = sys.argv[1], json.loads(sys.argv[2])
rest, erodible = json.loads(sys.argv[3]), json.loads(sys.argv[4])
lu = [f"numerics.linear_solver={solver}", "output.progress=false"]
out = {}
problem = build_problem(load_config("trapezoid-rigid", [*lu, "time.output_times=[]"]))
r = problem.simulation.run()
out["default_collapse"] = {"steps": r.steps, "rejected_steps": r.rejected_steps,
                           "iterations": r.nonlinear_iterations, "t_final": r.t_final,
                           "runout_m": problem.measures.front()}
for floor in (1e-3, 1e-7):
    for scenario, extra in (("cylinder-rigid", []), ("rectangle-rigid", ["geometry.width=0.1"])):
        problem = build_problem(load_config(scenario, [*extra, *rest, *lu,
                                                       f"numerics.velocity_floor={floor}"]))
        xy0 = problem.mesh.ngmesh.Coordinates().copy()
        r = problem.simulation.run()
        speed, _ = cell_means(problem.mesh, ngs.Norm(problem.solver.velocity))
        moved = np.abs(problem.mesh.ngmesh.Coordinates() - xy0).max()
        out[f"{scenario} floor {floor:g}"] = {"max_speed": float(speed.max()),
                                              "max_displacement": float(moved),
                                              "iterations": r.nonlinear_iterations}
for ahead in (0.0, 0.05):
    problem = build_problem(load_config("trapezoid-erodible", [*erodible, *lu,
                                                               f"mesh.layer_ahead={ahead}"]))
    problem.simulation.run()
    out[f"erosion_front_x layer_ahead {ahead:g}"] = problem.layer.measures()["erosion_front_x"]
    out[f"triangles layer_ahead {ahead:g}"] = problem.mesh.ne
if solver == "pardiso":
    for size in sizes:
        problem = build_problem(load_config("trapezoid-rigid", [f"mesh.size={size}", *lu]))
        flow = problem.solver
        flow.dt.Set(1e-3)
        system = flow.nonlinear.picard_system
        system.prepare()
        system.iterate(flow.solution.vec)
        system.assemble()
        free = flow.space.FreeDofs()
        inverse = system.a.mat.Inverse(free, inverse="pardiso", flags=Flags(PARDISO_FLAGS))
        repeat, medians = max(3, 200_000 // free.NumSet()), []
        for _ in range(5):
            start = time.process_time()
            for _ in range(repeat):
                inverse.Update()
            medians.append(1e3 * (time.process_time() - start) / repeat)
        out[f"refactorise_ms {free.NumSet()} unknowns"] = sorted(medians)[2]
print("RESULT " + json.dumps(out))
'''


def run_setting(setting: str, sizes: list[float]) -> dict:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
           "MKL_CBWR": "COMPATIBLE" if setting == "umfpack" else
           ("" if setting == "default" else setting)}
    solver = "umfpack" if setting == "umfpack" else "pardiso"
    arguments = [solver, *(json.dumps(x) for x in (sizes, REST, ERODIBLE))]
    done = subprocess.run([sys.executable, "-c", CHILD, *arguments], env=env,
                          capture_output=True, text=True, check=True)
    line = next(x for x in done.stdout.splitlines() if x.startswith("RESULT "))
    return json.loads(line.removeprefix("RESULT "))


def cpu_model() -> str:
    info = Path("/proc/cpuinfo")
    if info.exists():
        for line in info.read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return platform.processor()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--settings", nargs="+",
                        default=["COMPATIBLE", "AUTO", "AVX2", "AVX512", "default", "umfpack"])
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.02, 0.005])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/reproducibility"))
    args = parser.parse_args()
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = None
    result = {"cpu": cpu_model(), "packages": versions, "rest_case": REST, "settings": {}}
    args.out.mkdir(parents=True, exist_ok=True)
    for setting in args.settings:
        row = result["settings"][setting] = run_setting(setting, args.sizes)
        c = row["default_collapse"]
        print(f"{setting:10s} default collapse: {c['steps']} steps, {c['iterations']} "
              f"iterations, t {c['t_final']:.5f} s, runout {c['runout_m']:.5f} m")
        for key, value in row.items():
            if key.startswith(("cylinder", "rectangle")):
                print(f"{'':10s} {key}: speed {value['max_speed']:.3g} m/s, moved "
                      f"{value['max_displacement']:.3g} m")
            elif key.startswith(("refactorise", "erosion", "triangles")):
                print(f"{'':10s} {key}: {value:.5g}")
        write_json(args.out / "reproducibility.json", result, end="\n")


if __name__ == "__main__":
    main()
