"""Benchmark: the collapse over a 5 mm erodible layer and its surface tension.

Run: python benchmarks/erodible.py [--variants default lagrange layer4 always off
         fig5-rigid fig5-rigid-always coarse rigid-coarse fine rigid-fine]
         [--out benchmarks/results/erodible] [--rerun]

Each variant is a full run (about 15 min on one core for the erodible ones) into
OUT/runs/VARIANT; a variant whose summary.json exists is not rerun unless --rerun.
Writes OUT/erodible.json (status, stop times, runouts, counters of every variant), the
free-surface comparison of each variant with its reference at the output times (mean and
max distance), and OUT/free_surfaces.png: the erodible run against the rigid-bed run at
the paper's times (0.18, 0.3, 0.48, 0.66, 0.78, 1.02 s).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from common.results import read_results, report, write_json

import granflow
from granflow.config import load_config
from granflow.geometry.polylines import surface_distance
from granflow.io import profiles
from granflow.io.plots import save_figure

VARIANTS: dict[str, tuple[str, list[str], str | None]] = {
    # name: (scenario, overrides, reference variant for the surface comparison)
    "default": ("trapezoid-erodible", [], "rigid"),
    "lagrange": ("trapezoid-erodible", ["numerics.mesh_velocity=lagrange"], "default"),
    "layer4": ("trapezoid-erodible", ["mesh.layer_cells=4"], "default"),
    "always": ("trapezoid-erodible", ["surface_tension.trigger_angle_deg=0",
                                      "surface_tension.release_angle_deg=0"], "default"),
    "off": ("trapezoid-erodible", ["surface_tension.enabled=false"], "default"),
    "rigid": ("trapezoid-rigid", [], None),
    # the erodible-rigid runout difference under refinement of the bulk mesh (the layer's
    # cells, layer thickness / mesh.layer_cells, stay; "layer4" refines those)
    "coarse": ("trapezoid-erodible", ["mesh.size=0.042"], "rigid-coarse"),
    "rigid-coarse": ("trapezoid-rigid", ["mesh.size=0.042"], None),
    "fine": ("trapezoid-erodible", ["mesh.size=0.0105"], "rigid-fine"),
    "rigid-fine": ("trapezoid-rigid", ["mesh.size=0.0105"], None),
    "fig5-rigid": ("trapezoid-rigid", ["surface_tension.enabled=true"], "rigid"),
    "fig5-rigid-always": ("trapezoid-rigid", ["surface_tension.enabled=true",
                                              "surface_tension.trigger_angle_deg=0",
                                              "surface_tension.release_angle_deg=0"], "rigid"),
}
KEYS = ["status", "message", "t_final", "steps", "rejected_steps", "linear_solves",
        "wall_time_s", "stop_time_s", "all_cells_static_s", "runout_m", "runout_1mm_m",
        "volume_relative_error", "n_triangles", "remeshes", "surface_tension_steps",
        "min_triangle_quality"]
TIMES = (0.18, 0.3, 0.48, 0.66, 0.78, 1.02)


def bulk_stop(run: Path, fraction: float = 0.01) -> float | None:
    """First time after which at most ``fraction`` of the area flows (> 1 mm/s)."""
    d = np.genfromtxt(run / "diagnostics.csv", delimiter=",", names=True)
    idx = np.flatnonzero(d["flowing_fraction"] > fraction)
    return float(d["t"][idx[-1] + 1]) if idx.size and idx[-1] + 1 < len(d) else None


def surfaces(run: Path) -> dict[float, np.ndarray]:
    """The free surfaces at TIMES that the run wrote."""
    return profiles.curves(run, "free_surface", TIMES)


def eroding_mass(surface: np.ndarray, layer: float = 0.005) -> np.ndarray:
    """The free surface up to the front of the eroding mass (the rightmost point more than
    1 mm above the layer) and the next point, where it meets the layer: what a rigid-bed
    surface can be compared with (beyond lies the undisturbed layer, to 0.8 m)."""
    above = np.flatnonzero(surface[:, 1] > layer + 1e-3)
    return surface[: above.max() + 2] if above.size else surface


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--variants", nargs="+", default=list(VARIANTS))
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/erodible"))
    parser.add_argument("--rerun", action="store_true")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    store = args.out / "erodible.json"
    results = read_results(store)
    for name in args.variants:
        scenario, overrides, _ = VARIANTS[name]
        run = args.out / "runs" / name
        if args.rerun or not (run / "summary.json").exists():
            config = load_config(scenario, overrides)
            granflow.run(config, out=run, force=True)
        summary = json.loads((run / "summary.json").read_text())
        results[name] = {k: summary.get(k) for k in KEYS} | {
            "scenario": scenario, "overrides": overrides,
            "bulk_stop_1pct_s": bulk_stop(run)}
        report(name, results[name])
    for name, row in results.items():
        ref = VARIANTS[name][2]
        a, b = surfaces(args.out / "runs" / str(ref)), surfaces(args.out / "runs" / name)
        over_layer = VARIANTS[name][0] == "trapezoid-erodible"
        if ref and over_layer and VARIANTS[ref][0] == "trapezoid-rigid":
            b = {t: eroding_mass(x) for t, x in b.items()}
        if ref and ref in results and a and b:   # (runs no longer on disk keep their rows)
            row["surface_vs_" + ref + "_mm"] = {
                f"{t:g}": [round(1e3 * x, 3) for x in surface_distance(a[t], b[t])]
                for t in TIMES if t in a and t in b}
    write_json(store, results)
    plot(args.out)


def plot(out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ero, rigid = surfaces(out / "runs" / "default"), surfaces(out / "runs" / "rigid")
    if not ero or not rigid:
        return
    fig, axes = plt.subplots(len(TIMES), 1, figsize=(7, 9), sharex=True)
    for ax, t in zip(axes, TIMES, strict=True):
        if t in rigid:
            ax.plot(*rigid[t].T, "k:", label="rigid bed")
        if t in ero:
            ax.plot(*ero[t].T, "C0-", label="5 mm erodible layer")
        ax.set_ylabel("Z (m)")
        ax.text(0.98, 0.8, f"t = {t:g} s", transform=ax.transAxes, ha="right")
        ax.set_aspect("equal")
        ax.set_xlim(0, 0.8)
    axes[0].legend(fontsize=8, loc="upper center")
    axes[-1].set_xlabel("X (m)")
    fig.tight_layout()
    save_figure(fig, out / "free_surfaces.png", dpi=110)


if __name__ == "__main__":
    main()
