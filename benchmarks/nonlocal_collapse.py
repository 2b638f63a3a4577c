"""Benchmark: the nonlocal fluidity law on the rectangle of glass beads (20 x 14 cm) on a
rigid bed: to rest at 22 deg against the stopping height, the fluidity's condition on the
Coulomb bed, the coupling of the fluidity to the flow, and the cost against mu(I).

Run: python benchmarks/nonlocal_collapse.py [--cases rest bed bed_thickness coupling cost cap]
         [--out benchmarks/results/nonlocal]

- rest: 22 deg towards rest (time.stop_at_rest, to t_end = 11.5 s: the front is arrested
  near 3 s, the sheet behind it still creeps): the deposit's thickness normal to the bed
  behind its front and the free surface's spacing there (the cells' size), against the
  model's h_stop(22) = 2.68 mm and the beads' fit, 9.45 mm (reference/beads.py); the
  kinetic energy, largest speed and flowing fraction at 3 s and at the end.
- bed: boundary.bed_fluidity = "zero-flux" (the default) against "zero" at 16 and 22 deg to
  t = 3 s: runout, the front's position at 1 and 3 s, the kinetic energy.
- coupling: numerics.fluidity_coupling = "lagged" (the default) against "iterated" at 22 deg
  to t = 0.005 s (the start, where the fluidity grows from the creep's seed): steps,
  iterations, wall time.
- cap: the first 5e-5 s at 22 deg with material at rest held up to mu_2 (the law's) and
  without that bound (the law's friction_cap_deg set to None here), at most 100 iterations
  a step: steps, rejected steps, iterations, wall time.
- cost: the nonlocal law against the glass beads' mu(I) (the slope study's `glass-beads`)
  at 22 deg to t = 1 s, side by side, and the share of the nonlocal run's time spent in the
  fluidity's solves (timed around FluidityField.solve).

The glass beads: mu_s = tan 20.9 deg, b = 0.9377, A = 0.48, d = 0.53 mm, rho_s = 2500 kg/m^3,
the bed's Coulomb friction 25.5 deg loaded by its reaction, as the slope study
(benchmarks/erosion_slopes.py). Runs go to OUT/runs/NAME; a finished one is kept, a killed
one continues from its checkpoint.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import time
from pathlib import Path

import numpy as np
import pandas as pd
from common.results import read_results, report, write_results
from common.runs import run_or_continue

from granflow.config import load_config
from granflow.fem import fluidity as fluidity_module
from granflow.io import profiles
from granflow.reference import beads
from granflow.scenarios import fluidity as fluidity_scenario
from granflow.scenarios import materials
from granflow.scenarios.column import build_column
from granflow.scenarios.materials import nonlocal_law

NONLOCAL = ["material.rheology=nonlocal", "material.friction_angle_deg=20.9",
            "material.grain_diameter=0.00053"]
MU_I = ["material.rheology=mu-i", "material.friction_angle_deg=20.9",
        "material.mu_2_deg=32.76", "material.i0=0.279", "material.grain_diameter=0.00053"]
COMMON = ["boundary.normal_load=reaction", "output.checkpoint_every=100",
          "time.output_times=[]"]
SLOPE = 22.0
REST_END = 11.5   # s: the front is arrested near 3 s, the sheet still creeps at 11.5 s
KEYS = ["status", "message", "t_final", "steps", "rejected_steps", "nonlinear_iterations",
        "wall_time_s", "stop_time_s", "front_stop_time_s", "runout_m", "n_triangles",
        "remeshes"]


def summary_row(summary: dict) -> dict:
    return {k: summary.get(k) for k in KEYS}


def deposit_thickness(run: Path) -> dict:
    """The final free surface's height above the bed (the bed frame's z), interpolated
    along it, at 1, 2, 5, 10 and 20 cm behind the tip, and the median over the downslope
    half; the spacing of the surface's vertices over the last 10 cm (the cells' size)."""
    surface = profiles.final_profile(run, "free_surface")
    if not surface:
        return {}
    order = np.argsort(surface["x"])
    x, z = np.asarray(surface["x"])[order], np.asarray(surface["z"])[order]
    tip = float(x[z > 1e-6].max())
    out = {f"thickness_{d:g}cm_behind_tip_mm": 1e3 * float(np.interp(tip - d / 100, x, z))
           for d in (1, 2, 5, 10, 20)}
    near = x > tip - 0.1
    return out | {"tip_m": tip, "median_thickness_downslope_half_mm": 1e3 * float(
        np.median(np.interp(np.linspace(tip / 2, tip, 2001), x, z))),
        "surface_spacing_at_tip_mm": 1e3 * float(np.median(np.diff(x[near])))}


def motion(run: Path, times: tuple[float, ...]) -> dict:
    """The kinetic energy, largest speed and flowing fraction nearest each time."""
    table = pd.read_csv(run / "diagnostics.csv")
    out = {}
    for t in times:
        row = table.iloc[int((table["t"] - t).abs().argmin())]
        out |= {f"kinetic_energy_{t:g}s_J": float(row["kinetic_energy"]),
                f"max_speed_{t:g}s_m_s": float(row["max_speed"]),
                f"flowing_fraction_{t:g}s": float(row["flowing_fraction"])}
    return out


def rest(out: Path) -> dict:
    overrides = [*COMMON, *NONLOCAL, f"geometry.slope_deg={SLOPE}", f"time.t_end={REST_END}",
                 "time.stop_at_rest=true", f"time.output_times=[{REST_END}]"]
    folder = out / "runs" / "rest-22"
    row = summary_row(run_or_continue("rectangle-rigid", overrides, folder))
    config = load_config("rectangle-rigid", overrides)
    law = nonlocal_law(config.material, config.numerics.eps)
    return row | deposit_thickness(folder) | motion(folder, (3.0, REST_END)) | {
        "h_stop_model_mm": 1e3 * law.stopping_height(SLOPE),
        "h_stop_beads_mm": 1e3 * beads.stopping_height(SLOPE, law.grain_diameter)}


def bed_thickness(out: Path) -> dict:
    """The deposit's thickness behind the front of the bed condition's 22-degree runs."""
    return {condition: deposit_thickness(out / "runs" / f"bed-{condition}-22")
            for condition in ("zero-flux", "zero")}


def bed(out: Path) -> dict:
    rows = {}
    for slope in (16.0, 22.0):
        for condition in ("zero-flux", "zero"):
            name = f"bed-{condition}-{slope:g}"
            overrides = [*COMMON, *NONLOCAL, f"geometry.slope_deg={slope}", "time.t_end=3",
                         f"boundary.bed_fluidity={condition}", "time.stop_at_rest=true"]
            rows[name] = summary_row(run_or_continue("rectangle-rigid", overrides,
                                                     out / "runs" / name))
            report(name, rows[name])
    return rows


def coupling(out: Path) -> dict:
    rows = {}
    for mode in ("lagged", "iterated"):
        problem = build_column(load_config("rectangle-rigid", [
            *COMMON, *NONLOCAL, f"geometry.slope_deg={SLOPE}", "time.t_end=0.005",
            f"numerics.fluidity_coupling={mode}", "time.stop_at_rest=false"]))
        start = time.perf_counter()
        result = problem.simulation.run()
        rows[mode] = {"status": result.status, "steps": result.steps,
                      "rejected_steps": result.rejected_steps,
                      "nonlinear_iterations": result.nonlinear_iterations,
                      "wall_time_s": time.perf_counter() - start,
                      "front_m": problem.measures.front()}
        report(mode, rows[mode])
    return rows


def cost(out: Path) -> dict:
    """The two laws side by side (in this one process, one after the other), with the
    fluidity's solves timed."""
    spent = [0.0]
    solve = fluidity_module.FluidityField.solve

    def timed(self: fluidity_module.FluidityField, dt: float) -> float:
        start = time.perf_counter()
        try:
            return solve(self, dt)
        finally:
            spent[0] += time.perf_counter() - start

    rows = {}
    for name, law in (("mu-i", MU_I), ("nonlocal", NONLOCAL)):
        problem = build_column(load_config("rectangle-rigid", [
            *COMMON, *law, f"geometry.slope_deg={SLOPE}", "time.t_end=1.0",
            "time.stop_at_rest=false"]))
        fluidity_module.FluidityField.solve = timed           # type: ignore[method-assign]
        spent[0] = 0.0
        start = time.perf_counter()
        try:
            result = problem.simulation.run()
        finally:
            fluidity_module.FluidityField.solve = solve       # type: ignore[method-assign]
        wall = time.perf_counter() - start
        rows[name] = {"status": result.status, "steps": result.steps,
                      "nonlinear_iterations": result.nonlinear_iterations,
                      "wall_time_s": wall, "fluidity_solve_s": spent[0],
                      "fluidity_share": spent[0] / wall, "front_m": problem.measures.front(),
                      "wall_per_step_ms": 1e3 * wall / max(result.steps, 1)}
        report(name, rows[name])
    rows["ratio_wall"] = rows["nonlocal"]["wall_time_s"] / rows["mu-i"]["wall_time_s"]
    return rows


def cap(out: Path) -> dict:
    rows = {}
    original = materials.nonlocal_law
    for bounded in (True, False):
        config = load_config("rectangle-rigid", [
            *COMMON, *NONLOCAL, f"geometry.slope_deg={SLOPE}", "time.t_end=5e-5",
            "numerics.max_iterations=100", "time.stop_at_rest=false"])

        def law(*args, bounded=bounded, original=original, **kwargs):
            found = original(*args, **kwargs)
            return found if bounded else dataclasses.replace(found, friction_cap_deg=None)

        materials.nonlocal_law = law                          # type: ignore[assignment]
        fluidity_scenario.nonlocal_law = law                  # type: ignore[attr-defined]
        try:
            problem = build_column(config)
            start = time.perf_counter()
            result = problem.simulation.run()
        finally:
            materials.nonlocal_law = original                 # type: ignore[assignment]
            fluidity_scenario.nonlocal_law = original         # type: ignore[attr-defined]
        name = "held up to mu_2" if bounded else "unbounded"
        rows[name] = {"status": result.status, "t_final": result.t_final,
                      "steps": result.steps, "rejected_steps": result.rejected_steps,
                      "nonlinear_iterations": result.nonlinear_iterations,
                      "wall_time_s": time.perf_counter() - start}
        report(name, rows[name])
    return rows


CASES = {"rest": rest, "bed": bed, "bed_thickness": bed_thickness, "coupling": coupling,
         "cost": cost, "cap": cap}


def markdown(results: dict) -> list[str]:
    lines = ["# The nonlocal law on the rectangle of glass beads", ""]
    if "rest" in results:
        r = results["rest"]
        lines += ["## 22 deg towards rest", "",
                  f"status {r['status']} at t = {r['t_final']:.2f} s, front arrested at "
                  f"{r['front_stop_time_s']:.2f} s, runout {r['runout_m']:.3f} m; h_stop: model "
                  f"{r['h_stop_model_mm']:.2f} mm, beads' fit {r['h_stop_beads_mm']:.2f} mm; "
                  f"kinetic energy {r['kinetic_energy_3s_J']:.3g} J/m at 3 s, "
                  f"{r[f'kinetic_energy_{REST_END:g}s_J']:.3g} J/m at {REST_END:g} s (largest "
                  f"speed {r[f'max_speed_{REST_END:g}s_m_s']:.3g} m/s, flowing fraction "
                  f"{r[f'flowing_fraction_{REST_END:g}s']:.3f})", ""]
    thickness = {"rest-22 (zero-flux)": results.get("rest", {})} | {
        f"bed-{k}-22 at 3 s": v for k, v in results.get("bed_thickness", {}).items()}
    lines += ["| run | 1 cm | 2 cm | 5 cm | 10 cm | 20 cm behind the tip | median, downslope "
              "half | surface spacing at the tip |", "|---|---|---|---|---|---|---|---|"]
    for name, r in thickness.items():
        if "tip_m" in r:
            lines.append(f"| {name} | " + " | ".join(
                f"{r[f'thickness_{d}cm_behind_tip_mm']:.2f}" for d in (1, 2, 5, 10, 20))
                + f" | {r['median_thickness_downslope_half_mm']:.2f} | "
                f"{r['surface_spacing_at_tip_mm']:.1f} |")
    lines.append("")
    for case in ("bed", "coupling", "cost", "cap"):
        if case not in results:
            continue
        lines += [f"## {case}", "", "| run | " + " | ".join(KEYS[:8]) + " |",
                  "|---|" + "---|" * 8]
        for name, row in results[case].items():
            if isinstance(row, dict):
                lines.append(f"| {name} | " + " | ".join(
                    _fmt(row.get(k)) for k in KEYS[:8]) + " |")
        lines.append("")
        if case == "cost":
            c = results[case]
            lines += [f"wall time nonlocal / mu(I): {c['ratio_wall']:.2f}; the fluidity's "
                      f"solves: {100 * c['nonlocal']['fluidity_share']:.1f} % of the "
                      "nonlocal run", ""]
    return lines


def _fmt(value: object) -> str:
    if isinstance(value, float):
        return f"{value:.4g}" if math.isfinite(value) else str(value)
    return "-" if value is None else str(value)[:40]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=CASES)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/nonlocal"))
    args = parser.parse_args()
    store = args.out / "nonlocal_collapse.json"
    results = read_results(store)
    for case in args.cases:
        results[case] = CASES[case](args.out)
        report(case, results[case])
        write_results(args.out, "nonlocal_collapse", results, markdown(results), show=True)


if __name__ == "__main__":
    main()
