"""Benchmark: the collapses with the regularised Drucker-Prager law and with
mu(I), side by side, at the paper's section 5.2 set-up (fixed dt = 1e-3 s, tol = 1e-3).

Run: python benchmarks/rheologies.py [--shapes trapezoid rectangle] [--rerun]
         [--laws drucker-prager mu-i augmented-lagrangian]
         [--out benchmarks/results/rheologies]
     python benchmarks/rheologies.py --shapes trapezoid-erodible --laws drucker-prager mu-i
         --out benchmarks/results/rheologies_erodible
     python benchmarks/rheologies.py --laws drucker-prager augmented-lagrangian
         --set boundary.channel_width=0.1 --set boundary.side_wall_friction_deg=10.2
         --out benchmarks/results/rheologies_side_walls   (both methods in a 10 cm channel)

The erodible shape is `trapezoid-erodible` with its own steps (adaptive dt, deposition and
surface-tension limits), to rest, not the fixed-dt set-up of the rigid beds.

mu(I) (Jop, Forterre & Pouliquen 2006, Nature 441) with their glass-bead mu_2 = tan 32.76
deg, I0 = 0.279, d = 0.5 mm, rho_s = 2500 kg/m3 (the defaults of `material.*`; packing
fraction 1550/2500 = 0.62), and mu_s = tan 25.5 deg, the paper's friction angle, so that
the two laws share their static yield surface and differ only by the rate dependence.
The augmented Lagrangian rows are the unregularised Drucker-Prager law solved by ALG2
(fem/augmented_lagrangian.py, r from numerics.al_r = auto, then balanced). The wall-time
ratio AL / regularised is measured in one invocation (--rerun runs all six back to back).
Each run goes to OUT/runs/SHAPE-LAW; writes
OUT/rheologies.json and .md (stop time, runout, wall time, linear solves, distances of
the free surfaces and of the static/flowing interfaces from the Drucker-Prager run at the
paper's times of each shape) and OUT/SHAPE_free_surfaces.png.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

from common.cases import SCENARIO, SETUP
from common.results import report, write_results
from common.runs import distances_mm

import granflow
from granflow.config import ConfigError, load_config
from granflow.io import profiles
from granflow.io.plots import save_figure

# The regularised law with the paper's iteration (3.2), the method section 5.2 timed against
# ALG2 (and what these tables used before the column scenarios defaulted to primal-dual).
LAWS = {"drucker-prager": ["numerics.linearization=picard"],
        "mu-i": ["material.rheology=mu-i"],
        "augmented-lagrangian": ["numerics.method=augmented-lagrangian"]}
DEFAULT_SHAPES = ["trapezoid", "rectangle"]
# over the erodible layer the scenario's own steps (adaptive, deposition and tension limits)
SETUP_ERODIBLE = ["time.t_end=2.0", "time.stop_at_rest=true"]
PAPER_AL_RATIO = {"trapezoid": 7.8, "rectangle": 5.0}   # section 5.2: AL time / regularised
KEYS = ["status", "message", "t_final", "steps", "nonlinear_iterations", "linear_solves",
        "wall_time_s", "stop_time_s", "front_stop_time_s", "runout_m", "wall_height_m"]


def run_case(shape: str, law: str, out: Path, rerun: bool,
             extra: list[str] | None = None) -> dict:
    run = out / "runs" / f"{shape}-{law}"
    try:
        setup = SETUP_ERODIBLE if shape.endswith("erodible") else SETUP
        config = load_config(SCENARIO[shape], [*setup, *LAWS[law], *(extra or [])])
    except ConfigError as err:
        return {"status": "refused", "message": str(err)}
    if rerun or not (run / "summary.json").exists():
        granflow.run(config, out=run, force=True)
    summary = json.loads((run / "summary.json").read_text())
    return {k: summary.get(k) for k in KEYS}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--shapes", nargs="+", default=DEFAULT_SHAPES, choices=list(SCENARIO))
    parser.add_argument("--laws", nargs="+", default=list(LAWS), choices=list(LAWS))
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/rheologies"))
    parser.add_argument("--rerun", action="store_true")
    parser.add_argument("--set", dest="extra", action="append", default=[],
                        help="key=value for every run (e.g. a channel's side walls)")
    args = parser.parse_args()
    rows = []
    for shape in args.shapes:
        for law in args.laws:
            row = {"shape": shape, "law": law,
                   **run_case(shape, law, args.out, args.rerun, args.extra)}
            if law != "drucker-prager" and row["status"] != "refused":
                ref, run = args.out / "runs" / f"{shape}-drucker-prager", \
                    args.out / "runs" / f"{shape}-{law}"
                for kind in ("free_surface", "interface"):
                    row[f"{kind}_vs_dp_mm"] = distances_mm(ref, run, kind)
            rows.append(row)
            report("", row)
        plot(args.out, shape)
    write(args.out, rows)


def write(out: Path, rows: list[dict]) -> None:
    def fmt(x: float | None, digits: int) -> str:
        return "-" if x is None else f"{x:.{digits}f}"

    lines = ["Section 5.2 set-up: dt = 1e-3 s fixed, tol = 1e-3, run to rest (1 mm/s rule).", "",
             "| shape | law | status | stop (s) | front stops (s) | runout (m) | wall time (s) "
             "| linear solves |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['shape']} | {r['law']} | {r['status']} | "
                     f"{fmt(r.get('stop_time_s'), 3)} | {fmt(r.get('front_stop_time_s'), 3)} | "
                     f"{fmt(r.get('runout_m'), 4)} | {fmt(r.get('wall_time_s'), 0)} | "
                     f"{r.get('linear_solves', '-')} |")
    for shape in dict.fromkeys(r["shape"] for r in rows):
        by_law = {r["law"]: r for r in rows if r["shape"] == shape}
        dp, al = by_law.get("drucker-prager", {}), by_law.get("augmented-lagrangian", {})
        if dp.get("wall_time_s") and al.get("wall_time_s"):
            paper = PAPER_AL_RATIO.get(shape)    # the paper ran no AL over the layer
            lines.append(f"- {shape}: augmented Lagrangian / regularised cost: wall "
                         f"{al['wall_time_s'] / dp['wall_time_s']:.2f}, linear solves "
                         f"{al['linear_solves'] / dp['linear_solves']:.2f} (paper: "
                         f"{'-' if paper is None else f'{paper:g}'})")
    lines += ["", "Distances from the Drucker-Prager run, mean/max (mm), at the paper's times:"]
    for r in rows:
        for key in ("free_surface_vs_dp_mm", "interface_vs_dp_mm"):
            if r.get(key):
                text = ", ".join(f"{t} s: {a}/{b}" for t, (a, b) in r[key].items())
                lines.append(f"- {r['shape']} {r['law']} {key[:-9]}: {text}")
    write_results(out, "rheologies", rows, lines, show=True)


def plot(out: Path, shape: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    runs = {law: profiles.curves(out / "runs" / f"{shape}-{law}", "free_surface") for law in LAWS
            if (out / "runs" / f"{shape}-{law}" / "config.toml").exists()}
    runs = {law: family for law, family in runs.items() if family}
    if "drucker-prager" not in runs:
        return
    times = sorted(runs["drucker-prager"])
    fig, axes = plt.subplots(len(times), 1, figsize=(7, 9), sharex=True)
    for ax, t in zip(axes, times, strict=True):
        for (law, family), style in zip(runs.items(), ("k-", "C1--", "C2:"), strict=False):
            if t in family:
                ax.plot(*family[t].T, style, label=law)
        ax.set_ylabel("Z (m)")
        ax.text(0.98, 0.8, f"t = {t:g} s", transform=ax.transAxes, ha="right")
        ax.set_aspect("equal")
    axes[0].legend(fontsize=8, loc="upper center")
    axes[-1].set_xlabel("X (m)")
    fig.tight_layout()
    save_figure(fig, out / f"{shape}_free_surfaces.png", dpi=110)


if __name__ == "__main__":
    main()
