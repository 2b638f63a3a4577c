"""Benchmark: which rigid bed (``boundary.bed``) reproduces the paper's collapses with the
rate-dependent laws, and the nonlocal law's deposit on a bed that does not slide.

Run: python benchmarks/bed_models.py [--cases flat rest] [--levels 0.014 0.007]
         [--viscosity 0.01] [--channel-width 0.1] [--laws glass-beads nonlocal]
         [--beds material no-slip]
         [--shapes rectangle trapezoid] [--out benchmarks/results/bed_models]

- flat: the paper's rectangle and trapezoid on the level bed (`rectangle-rigid`,
  `trapezoid-rigid` at their settings, to rest or 3 s) with Drucker-Prager (the paper's law: on the
  25.5-degree Coulomb bed the model the paper shows against the experiments), the glass
  beads' mu(I) and the nonlocal law (Henann & Kamrin's beads, as benchmarks/erosion_slopes.py),
  each on the Coulomb bed, the no-slip bed and the material bed (Drucker-Prager's material
  bed is its Coulomb bed, not run again): stop time, runout, and the final free surface's
  mean and largest distance from the Drucker-Prager run on the Coulomb bed.
- rest: the nonlocal glass beads' rectangle at 22 deg on the no-slip bed (g = 0 on it) to
  rest (t_end 30 s, time.stop_at_rest) at each mesh size of --levels: the deposit's
  thickness behind its tip against the model's h_stop(22) = 2.68 mm
  (``nonlocal_collapse.deposit_thickness``), the time it came to rest, its runout.

``--viscosity ETA`` runs the flat case with material.viscosity = ETA (the paper's 1 Pa s
otherwise), its runs named NAME-etaETA beside the others; every flat row is compared with
Drucker-Prager on the Coulomb bed at the paper's 1 Pa s (the model the paper shows against
the experiments). ``--channel-width W`` puts the flat runs in the experiments' channel
(boundary.channel_width = W: the side walls' depth-averaged drag (2 mu_w / W) p at the
default wall friction), named NAME[-etaETA]-wallsW. ``--laws``, ``--beds`` and ``--shapes``
run a part of the flat case.

Runs go to OUT/runs/NAME (checkpoints every 100 steps: a killed study continues where it
stopped); OUT/bed_models.json holds every figure, OUT/bed_models.md the tables.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
from common.results import read_results, report, write_results
from common.runs import run_or_continue
from nonlocal_collapse import deposit_thickness, motion

from granflow.config import load_config
from granflow.diagnostics.compare import surface_distance
from granflow.io import profiles
from granflow.scenarios.materials import nonlocal_law

LAWS = {
    "drucker-prager": [],
    "glass-beads": ["material.rheology=mu-i", "material.friction_angle_deg=20.9",
                    "material.mu_2_deg=32.76", "material.i0=0.279",
                    "material.grain_diameter=0.00053"],
    "nonlocal": ["material.rheology=nonlocal", "material.friction_angle_deg=20.9",
                 "material.grain_diameter=0.00053"],
}
BEDS = ("coulomb", "no-slip", "material")
SHAPES = {"rectangle": "rectangle-rigid", "trapezoid": "trapezoid-rigid"}
COMMON = ["output.checkpoint_every=100"]
KEYS = ["status", "message", "t_final", "steps", "rejected_steps", "nonlinear_iterations",
        "wall_time_s", "stop_time_s", "front_stop_time_s", "runout_m", "n_triangles",
        "remeshes"]
REST_SLOPE, REST_END = 22.0, 30.0
FLAT_END = 3.0   # s: every level-bed run to rest (the rate-dependent laws creep longer)


def store(out: Path, case: str, name: str, row: dict) -> None:
    """The row into OUT/bed_models.json as it is on disk now: two invocations running
    different rows at once keep each other's rows."""
    results = read_results(out / "bed_models.json")
    results.setdefault(case, {})[name] = row
    write_results(out, "bed_models", results)


def final_surface(run: Path) -> np.ndarray | None:
    """The last accepted state's free surface, (n, 2)."""
    surface = profiles.final_profile(run, "free_surface")
    if not surface:
        return None
    return np.column_stack([surface["x"], surface["z"]])


def run_tail(viscosity: float | None, channel_width: float | None) -> str:
    """The suffix naming a flat run's viscosity and channel: -etaETA, -wallsW."""
    return (("" if viscosity is None else f"-eta{viscosity:g}")
            + ("" if channel_width is None else f"-walls{channel_width:g}"))


def flat(out: Path, results: dict, viscosity: float | None = None,
         laws: tuple[str, ...] = tuple(LAWS), beds: tuple[str, ...] = BEDS,
         shapes: tuple[str, ...] = tuple(SHAPES), channel_width: float | None = None) -> dict:
    """The level-bed runs of ``shapes`` x ``laws`` x ``beds`` (``viscosity``: eta, Pa s,
    else the paper's; ``channel_width``: side walls, m, else none), each kept when finished
    and continued from its checkpoint."""
    rows = results.setdefault("flat", {})
    tail = run_tail(viscosity, channel_width)
    eta = [] if viscosity is None else [f"material.viscosity={viscosity!r}"]
    if channel_width is not None:
        eta.append(f"boundary.channel_width={channel_width!r}")
    for shape in shapes:
        scenario = SHAPES[shape]
        reference = out / "runs" / f"{shape}-drucker-prager-coulomb"
        for law in laws:
            for bed in beds:
                if law == "drucker-prager" and bed == "material":
                    continue       # its Coulomb bed, to round-off (tests/unit/test_bed.py)
                name = f"{shape}-{law}-{bed}{tail}"
                folder = out / "runs" / name
                overrides = [*COMMON, *LAWS[law], *eta, f"boundary.bed={bed}",
                             f"time.t_end={FLAT_END}"]
                row = {k: v for k, v in run_or_continue(scenario, overrides, folder).items()
                       if k in KEYS}
                first, second = final_surface(folder), final_surface(reference)
                if first is not None and second is not None:
                    mean, worst = surface_distance(first, second)
                    row |= {"surface_to_paper_model_mean_mm": 1e3 * mean,
                            "surface_to_paper_model_max_mm": 1e3 * worst}
                rows[name] = row | {"overrides": overrides}
                report(name, {k: row.get(k) for k in (
                    "status", "stop_time_s", "runout_m", "surface_to_paper_model_mean_mm")})
                store(out, "flat", name, rows[name])
    return rows


def rest(out: Path, results: dict, levels: list[float]) -> dict:
    rows = results.setdefault("rest", {})
    for size in levels:
        name = f"rest-{REST_SLOPE:g}-{1e3 * size:g}mm"
        folder = out / "runs" / name
        overrides = [*COMMON, *LAWS["nonlocal"], "boundary.normal_load=reaction",
                     "numerics.anderson_depth=3",   # (3.2) 2-cycles at the held front
                     "boundary.bed=no-slip", f"geometry.slope_deg={REST_SLOPE}",
                     f"mesh.size={size!r}", f"time.t_end={REST_END}",
                     "time.stop_at_rest=true", f"time.output_times=[{REST_END}]"]
        row = {k: v for k, v in run_or_continue("rectangle-rigid", overrides, folder).items()
               if k in KEYS}
        config = load_config("rectangle-rigid", overrides)
        law = nonlocal_law(config.material, config.numerics.eps)
        rows[name] = (row | deposit_thickness(folder) | motion(folder, (3.0,))
                      | {"h_stop_model_mm": 1e3 * law.stopping_height(REST_SLOPE),
                         "mesh_size_mm": 1e3 * size, "overrides": overrides})
        report(name, {k: rows[name].get(k) for k in (
            "status", "stop_time_s", "runout_m", "thickness_5cm_behind_tip_mm")})
        store(out, "rest", name, rows[name])
    return rows


def figure(out: Path, tail: str = "") -> None:
    """The final free surfaces on the level bed: per column and law, its three beds (the
    runs named with ``tail``: a viscosity's), with Drucker-Prager on the Coulomb bed at the
    paper's viscosity (black) under each; OUT/bed_models{tail}.png."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from granflow.io.plots import save_figure

    laws = [law for law in LAWS if law != "drucker-prager"]
    fig, axes = plt.subplots(len(SHAPES), len(laws) + 1, figsize=(13, 5.5), squeeze=False)
    for row, shape in zip(axes, SHAPES, strict=True):
        reference = final_surface(out / "runs" / f"{shape}-drucker-prager-coulomb")
        for ax, law in zip(row, ["drucker-prager", *laws], strict=True):
            if reference is not None:
                ax.plot(reference[:, 0], reference[:, 1], "k-", lw=2, label="DP, coulomb")
            for bed, style in zip(BEDS, ("-", "--", ":"), strict=True):
                surface = final_surface(out / "runs" / f"{shape}-{law}-{bed}{tail}")
                if surface is not None and (law, bed) != ("drucker-prager", "coulomb"):
                    ax.plot(surface[:, 0], surface[:, 1], style, label=bed)
            ax.set_title(f"{shape}, {law}", fontsize=9)
            ax.set_xlabel("x (m)")
            ax.legend(fontsize=7)
        row[0].set_ylabel("z (m)")
    save_figure(fig, out / f"bed_models{tail}.png")


def markdown(results: dict) -> list[str]:
    lines = ["# The rigid bed's models on the paper's collapses", ""]
    flat_rows = results.get("flat", {})
    if flat_rows:
        lines += ["## The level bed: stop time, runout, final surface against Drucker-Prager "
                  "on the Coulomb bed (eta = 1 Pa s: the paper's model)", "",
                  "| column | law | bed | eta (Pa s) | side walls | stop (s) | runout (m) | "
                  "runout against the paper's model | surface: mean / max (mm) |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for name, r in flat_rows.items():
            shape, rest_of = name.split("-", 1)
            law = next(k for k in LAWS if rest_of.startswith(k))
            named, _, walls = rest_of[len(law) + 1:].partition("-walls")
            bed, _, eta = named.partition("-eta")
            channel = f"{walls} m" if walls else "no"
            paper = flat_rows.get(f"{shape}-drucker-prager-coulomb", {}).get("runout_m")
            change = "-" if not paper else f"{100 * (r['runout_m'] / paper - 1):+.1f} %"
            stop = ("-" if r.get("stop_time_s") is None else f"{r['stop_time_s']:.3f}") + (
                f" (moving at {r['t_final']:g} s)" if r.get("status") == "completed" else "")
            surface = ("-" if "surface_to_paper_model_mean_mm" not in r else
                       f"{r['surface_to_paper_model_mean_mm']:.1f} / "
                       f"{r['surface_to_paper_model_max_mm']:.1f}")
            lines.append(f"| {shape} | {law} | {bed} | {eta or '1'} | {channel} | {stop} | "
                         f"{r['runout_m']:.4f} | {change} | {surface} |")
        lines.append("")
    rest_rows = results.get("rest", {})
    if rest_rows:
        lines += [f"## The nonlocal beads at {REST_SLOPE:g} deg on the no-slip bed, to rest",
                  "", "| mesh size (mm) | status | at rest (s) | runout (m) | deposit 1 / 2 / 5 / "
                  "10 / 20 cm behind the tip (mm) | surface spacing at the tip (mm) | "
                  "h_stop (mm) |", "|---|---|---|---|---|---|---|"]
        for r in rest_rows.values():
            thick = " / ".join(f"{r.get(f'thickness_{d}cm_behind_tip_mm', float('nan')):.2f}"
                               for d in (1, 2, 5, 10, 20))
            stop = "-" if r.get("stop_time_s") is None else f"{r['stop_time_s']:.2f}"
            lines.append(f"| {r['mesh_size_mm']:g} | {r['status']} | {stop} | "
                         f"{r['runout_m']:.3f} | {thick} | "
                         f"{r.get('surface_spacing_at_tip_mm', float('nan')):.1f} | "
                         f"{r['h_stop_model_mm']:.2f} |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", nargs="+", default=["flat", "rest"],
                        choices=["flat", "rest"])
    parser.add_argument("--levels", nargs="+", type=float, default=[0.014])
    parser.add_argument("--viscosity", type=float, default=None,
                        help="flat case: material.viscosity (Pa s); the paper's 1 otherwise")
    parser.add_argument("--channel-width", type=float, default=None,
                        help="flat case: boundary.channel_width (m), the side walls; none "
                        "otherwise")
    parser.add_argument("--laws", nargs="+", default=list(LAWS), choices=LAWS)
    parser.add_argument("--beds", nargs="+", default=list(BEDS), choices=BEDS)
    parser.add_argument("--shapes", nargs="+", default=list(SHAPES), choices=SHAPES)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/bed_models"))
    args = parser.parse_args()
    results = read_results(args.out / "bed_models.json")
    if "flat" in args.cases:
        flat(args.out, results, args.viscosity, tuple(args.laws), tuple(args.beds),
             tuple(args.shapes), args.channel_width)
    if "rest" in args.cases:
        rest(args.out, results, args.levels)
    results = read_results(args.out / "bed_models.json")    # with rows run meanwhile
    write_results(args.out, "bed_models", results, markdown(results), show=True)
    if "flat" in args.cases:
        figure(args.out, run_tail(args.viscosity, args.channel_width))


if __name__ == "__main__":
    main()
