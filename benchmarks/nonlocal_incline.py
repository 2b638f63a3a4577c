"""Benchmark: the nonlocal fluidity law on the rough incline, finer than the tests
(tests/verification/test_nonlocal.py, test_fluidity_mms.py): the stopping height against
the model's own threshold and the beads' fit, layers released in motion, Pouliquen's flow
rule, the local limit and the manufactured solution.

Run: python benchmarks/nonlocal_incline.py [--studies hstop motion flowrule local mms]
         [--out benchmarks/results/nonlocal]

- hstop: at 22, 23, 24, 25.5, 27, 28 and 30 deg, the growth rate of a small fluidity
  (1e-3 of the local state's, at rest) in layers of 0.9, 0.95, 1.05 and 1.1 h_stop (16 cells
  across, dt = 5e-3 s, the log-slope over t = 0.5-1.5 s); its zero, interpolated in 1 / h^2,
  is the computed h_stop: against (pi / 2) A d / sqrt(tan - mu_s) (the code against its
  theory) and the beads' fit (reference/beads.py); and the one A that fits the beads best
  (least squares in log h_stop) with the ratios it gives.
- motion: layers of 0.9 and 1.1 h_stop at 25.5 deg released in motion (the local steady
  fluidity, u = 0 at t = 0) to t = 10 s: the largest speed at the end, against the 1D
  steady flow (reference/nonlocal_incline.py).
- flowrule: Froude number u_mean / sqrt(g h cos) against h / h_stop from the 1D steady flow
  at six angles and h / h_stop = 1.5 to 20, with the model's h_stop and with the fit's; the
  slope beta of a line through the origin (Pouliquen: 0.136); two points checked with the
  2D solver (its steady state against the 1D one).
- local: A = 0 at 23 deg, 8, 16 and 32 cells across: the relative L2 error against Bagnold's
  profile of mu_s + b I, with eta = 1e-6 Pa s and with the scenario's 1e-4 Pa s.
- mms: the manufactured solution on a moving mesh at h = 1/4 ... 1/32 and its orders.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np
from common.results import read_results, report, write_results

from granflow.config import load_config
from granflow.reference import beads
from granflow.reference.incline import bagnold
from granflow.reference.nonlocal_incline import steady_nonlocal_flow
from granflow.scenarios.fluidity import fluidity_growth_rate
from granflow.scenarios.materials import nonlocal_law
from granflow.scenarios.plug_flow import build_plug_flow

NONLOCAL = ["material.rheology=nonlocal", "time.output_times=[]", "material.viscosity=1e-4"]
SLOPES = [22.0, 23.0, 24.0, 25.5, 27.0, 28.0, 30.0]
FACTORS = [0.9, 0.95, 1.05, 1.1]
DENSITY, GRAVITY = 1500.0, 9.81


def law(*overrides: str):
    config = load_config("incline-mu-i", [*NONLOCAL, *overrides])
    return nonlocal_law(config.material, config.numerics.eps)


def layer(slope: float, height: float, cells: int, *extra: str):
    size = height / cells
    return build_plug_flow(load_config("incline-mu-i", [
        *NONLOCAL, f"mesh.size={size}", f"geometry.length={2 * size}",
        f"geometry.height={height}", "initial.plug_base=0", "initial.shear_rate=0",
        f"geometry.slope_deg={slope}", *extra]))


def growth_rate(slope: float, factor: float, cells: int = 16) -> float:
    h = factor * law().stopping_height(slope)
    problem = layer(slope, h, cells, "initial.fluidity=1e-3", "time.dt=5e-3",
                    "time.t_end=1.5")
    return fluidity_growth_rate(problem.solver, problem.simulation, problem.mesh, after=0.5)


def hstop() -> dict:
    rows = {}
    d = law().grain_diameter
    for slope in SLOPES:
        rates = [growth_rate(slope, f) for f in FACTORS]
        x = 1 / np.array(FACTORS) ** 2
        fit = np.polyfit(x, rates, 1)
        computed = law().stopping_height(slope) / math.sqrt(-fit[1] / fit[0])
        theory, fitted = law().stopping_height(slope), beads.stopping_height(slope, d)
        rows[f"{slope:g}"] = {"rates": rates, "h_stop_computed_mm": 1e3 * computed,
                              "h_stop_theory_mm": 1e3 * theory,
                              "computed_over_theory": computed / theory,
                              "h_stop_beads_mm": 1e3 * fitted,
                              "model_over_beads": theory / fitted}
        report(f"hstop {slope:g}", rows[f"{slope:g}"])
    logs = [math.log(r["h_stop_beads_mm"] / r["h_stop_theory_mm"]) for r in rows.values()]
    scale = math.exp(float(np.mean(logs)))
    amplitude = law().amplitude * scale
    return {"slopes": rows, "calibrated_amplitude": amplitude,
            "calibrated_model_over_beads": {k: r["model_over_beads"] * scale
                                            for k, r in rows.items()}}


def motion() -> dict:
    rows = {}
    slope = 25.5
    for factor in (0.9, 1.1):
        h = factor * law().stopping_height(slope)
        problem = layer(slope, h, 16, "initial.fluidity=1", "time.dt=0.01", "time.t_end=10")
        problem.simulation.run()
        z, u, _ = problem.profile(problem.simulation.t)
        steady = steady_nonlocal_flow(law=law(), height=h, slope_deg=slope, density=DENSITY)
        rows[f"{factor:g}"] = {"height_mm": 1e3 * h, "top_speed_m_s": float(np.abs(u).max()),
                               "steady_1d_top_speed_m_s": float(steady.u.max()),
                               "steady_1d_flowing": steady.flowing}
        report(f"motion {factor:g}", rows[f"{factor:g}"])
    return rows


def flowrule() -> dict:
    ratios = [1.5, 2.0, 3.0, 5.0, 8.0, 12.0, 20.0]
    out: dict = {"angles": {}}
    d = law().grain_diameter
    for slope in SLOPES[:-1]:
        h_stop = law().stopping_height(slope)
        rows = []
        for ratio in ratios:
            h = ratio * h_stop
            flow = steady_nonlocal_flow(law=law(), height=h, slope_deg=slope, density=DENSITY)
            froude = flow.mean_velocity / math.sqrt(GRAVITY * h * math.cos(math.radians(slope)))
            rows.append({"h_over_h_stop": ratio, "height_mm": 1e3 * h, "froude": froude,
                         "h_over_h_stop_beads": h / beads.stopping_height(slope, d)})
        out["angles"][f"{slope:g}"] = rows
    for which in ("h_over_h_stop", "h_over_h_stop_beads"):
        x = np.array([r[which] for rows in out["angles"].values() for r in rows])
        y = np.array([r["froude"] for rows in out["angles"].values() for r in rows])
        beta = float(x @ y / (x @ x))
        out[f"beta_{which}"] = beta
        out[f"spread_{which}"] = float(np.std(y / (beta * x)))
    checks = {}
    for slope, ratio in ((25.5, 3.0), (25.5, 8.0)):
        h = ratio * law().stopping_height(slope)
        problem = layer(slope, h, 16, "initial.fluidity=1", "time.dt=0.01", "time.t_end=8")
        problem.simulation.run()
        checks[f"{slope:g}/{ratio:g}"] = problem.velocity_error(problem.simulation.t)
    out["checks_2d_relative_l2"] = checks
    report("flowrule", {k: v for k, v in out.items() if k != "angles"})
    return out


def local() -> dict:
    rows = {}
    beads_law = law("material.nonlocal_amplitude=0")
    i_theta = beads_law.local_inertial_number(math.tan(math.radians(23.0)))
    exact = bagnold(height=0.01, slope_deg=23.0, inertial_number=i_theta,
                    grain_diameter=beads_law.grain_diameter,
                    packing=DENSITY / beads_law.grain_density)
    for viscosity in ("1e-6", "1e-4"):
        for cells in (8, 16, 32):
            problem = build_plug_flow(load_config("incline-mu-i", [
                *NONLOCAL, "material.nonlocal_amplitude=0", "initial.fluidity=1",
                f"material.viscosity={viscosity}", "geometry.slope_deg=23", "time.dt=5e-3",
                "time.t_end=3", f"mesh.size={0.01 / cells}"]))
            problem.simulation.run()
            z, u, _ = problem.profile(problem.simulation.t)
            ref = exact(z)
            name = f"eta {viscosity}, {cells} cells"
            rows[name] = math.sqrt(np.trapezoid((u[:, 0] - ref) ** 2, z)
                                   / np.trapezoid(ref**2, z))
            report(f"local {name}", rows[name])
    return rows


def mms() -> dict:
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "verification"))
    from test_fluidity_mms import l2_error

    sizes = [0.25, 0.125, 0.0625, 0.03125]
    errors = [l2_error(h) for h in sizes]
    orders = [math.log(errors[k] / errors[k + 1]) / math.log(2) for k in range(len(sizes) - 1)]
    return {"h": sizes, "l2_error": errors, "orders": orders}


STUDIES = {"hstop": hstop, "motion": motion, "flowrule": flowrule, "local": local, "mms": mms}


def markdown(results: dict) -> list[str]:
    lines = ["# The nonlocal law on the incline", ""]
    if "hstop" in results:
        r = results["hstop"]
        lines += ["| slope | h_stop computed (mm) | theory (mm) | ratio | beads' fit (mm) | "
                  "model / fit | with A calibrated |", "|---|---|---|---|---|---|---|"]
        for slope, row in r["slopes"].items():
            lines.append(f"| {slope}° | {row['h_stop_computed_mm']:.3f} | "
                         f"{row['h_stop_theory_mm']:.3f} | {row['computed_over_theory']:.4f} | "
                         f"{row['h_stop_beads_mm']:.2f} | {row['model_over_beads']:.2f} | "
                         f"{r['calibrated_model_over_beads'][slope]:.2f} |")
        lines += ["", f"A fitted to the beads (least squares in log h_stop): "
                  f"{r['calibrated_amplitude']:.3f}", ""]
    if "flowrule" in results:
        r = results["flowrule"]
        lines += [f"Flow rule: beta = {r['beta_h_over_h_stop']:.4f} against the model's h_stop "
                  f"(scatter {r['spread_h_over_h_stop']:.3f}), "
                  f"{r['beta_h_over_h_stop_beads']:.4f} against the beads' fit (scatter "
                  f"{r['spread_h_over_h_stop_beads']:.3f}); Pouliquen: 0.136. 2D steady "
                  f"states against the 1D: {r['checks_2d_relative_l2']}", ""]
    for name in ("motion", "local", "mms"):
        if name in results:
            lines += [f"{name}: {results[name]}", ""]
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--studies", nargs="+", default=list(STUDIES), choices=STUDIES)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/nonlocal"))
    args = parser.parse_args()
    results = read_results(args.out / "nonlocal_incline.json")
    for study in args.studies:
        results[study] = STUDIES[study]()
        write_results(args.out, "nonlocal_incline", results, markdown(results), show=True)


if __name__ == "__main__":
    main()
