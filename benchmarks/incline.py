"""Benchmark: steady flow down an incline against the exact profiles.

Run: python benchmarks/incline.py [--cells 8 16 32] [--out benchmarks/results/incline]

A periodic layer h = 1 cm starting at rest on a slope steeper than its static friction
(scenario `incline-mu-i`, Jop et al. 2006 glass beads) runs to t = 8 s; `steadiness` is
the relative change of the surface speed over the last 2 s (the layer has reached its
steady state when it is far below the error):

- mu(I) at 23 and 27 deg (I_theta = 0.054 and 0.27), viscosity 1e-4 Pa s beside mu(I):
  the relative L2 error over the layer against the exact steady profile of the same law
  (reference/incline.py: mu_i_profile) and, along the mid vertical, against Bagnold's
  formula (eta = 0);
- Drucker-Prager (2.13) with the same mu_s, eta = 0.5 Pa s at 25 deg: against the parabola.

Each at --cells across the depth (mesh.size = h / cells, 2 cells along), dt = 2e-3 s,
Newton, eps = 1e-6. Writes OUT/incline.json and OUT/incline.md.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path

import numpy as np
from common.results import report, write_results

import granflow
from granflow.config import load_config
from granflow.io import profiles
from granflow.io.run_dir import RunDir
from granflow.physics import MuI
from granflow.reference.incline import bagnold_profile
from granflow.scenarios.materials import build_rheology

HEIGHT = 0.01
CASES = {   # name: overrides of incline-mu-i
    "mu-i 23 deg": ["geometry.slope_deg=23"],
    "mu-i 27 deg": ["geometry.slope_deg=27"],
    "drucker-prager 25 deg": ["geometry.slope_deg=25", "material.rheology=drucker-prager",
                              "material.viscosity=0.5", "material.mu_2_deg=32.76",
                              "material.i0=0.279", "material.grain_diameter=0.0005",
                              "material.grain_density=2500"],
}


def profile(found: profiles.ProfileFile) -> tuple[np.ndarray, np.ndarray]:
    """(z, u_x) of a velocity profile."""
    data = found.read()
    return data["z"], data["u_x"]


def output_profiles(run_dir: Path) -> list[profiles.ProfileFile]:
    """The velocity profiles at the output times, in time order."""
    return [p for p in profiles.list_profiles(run_dir, "velocity") if not p.final]


def steadiness(run_dir: Path) -> float:
    """|u_surface(8 s) - u_surface(6 s)| / u_surface(8 s)."""
    (_, u6), (_, u8) = (profile(p) for p in output_profiles(run_dir))
    return abs(u8[-1] - u6[-1]) / abs(u8[-1])


def bagnold_error(config, run_dir: Path) -> float | None:
    """Relative L2 difference of the final mid-vertical profile from Bagnold's formula."""
    law = build_rheology(config)
    if not isinstance(law, MuI):
        return None
    law0 = dataclasses.replace(law, viscosity=0.0)
    exact = bagnold_profile(height=HEIGHT, slope_deg=config.geometry.slope_deg, law=law0,
                            density=config.material.density, gravity=config.material.gravity)
    z, u = profile(output_profiles(run_dir)[-1])
    ref = exact(z)
    return math.sqrt(np.trapezoid((u - ref) ** 2, z) / np.trapezoid(ref**2, z))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cells", nargs="+", type=int, default=[8, 16, 32])
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/incline"))
    args = parser.parse_args()
    results = []
    for name, overrides in CASES.items():
        for cells in args.cells:
            sets = [*overrides, f"mesh.size={HEIGHT / cells!r}", "time.t_end=8.0",
                    "time.output_times=[6.0, 8.0]", "material.viscosity=1e-4"
                    if "mu-i" in name else "material.viscosity=0.5"]
            config = load_config("incline-mu-i", sets)
            folder = args.out / "runs" / f"{name.replace(' ', '_')}_{cells}"
            run_dir = granflow.run(config, out=folder, force=True)
            s = RunDir.summary(run_dir.root)
            row = {"case": name, "cells": cells, "dt": config.time.dt, "status": s["status"],
                   "error_exact": s["velocity_relative_error_l2"],
                   "error_bagnold": bagnold_error(config, run_dir.root),
                   "steadiness": steadiness(run_dir.root),
                   "steps": s["steps"], "iterations": s["nonlinear_iterations"],
                   "wall_time_s": s["wall_time_s"]}
            results.append(row)
            report("", row)
    lines = ["| case | cells across h | dt (s) | L2 error vs exact steady profile | "
             "L2 error vs Bagnold (eta = 0) | steadiness | Newton iterations / steps | wall (s) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in results:
        bag = "-" if r["error_bagnold"] is None else f"{r['error_bagnold']:.2e}"
        lines.append(f"| {r['case']} | {r['cells']} | {r['dt']:g} | {r['error_exact']:.2e} | "
                     f"{bag} | {r['steadiness']:.0e} | {r['iterations']} / {r['steps']} | "
                     f"{r['wall_time_s']:.1f} |")
    write_results(args.out, "incline", results, lines, show=True)


if __name__ == "__main__":
    main()
