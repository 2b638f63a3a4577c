"""Benchmark: what the numerical surface tension's gamma0-bar scales with
(``surface_tension.length``), over a layer stronger than the column and on the verified
erodible collapses.

Run: python benchmarks/tension_length.py [--lengths mesh_size local_edge off]
         [--cases strong-60-0.04 ... trapezoid-erodible cylinder-erodible]
         [--out benchmarks/results/tension_length]

gamma0-bar of (3.11) is the pressure under the fold times a length: ``mesh_size`` (the
paper's uniform mesh size, granflow's default) or ``local_edge`` (each surface node's own
edge length, the denominator of C in (3.10), so gamma = pressure x turning angle). Over a
layer meshed finer than the column the two differ by mesh.size over the layer's edge.
Each case runs with each length into OUT/runs/LENGTH/CASE (kept when finished, continued
from a checkpoint); OUT/tension_length.json holds the summaries' figures, the strong
layer's iterations and displaced layer over the one-material run's, and the two lengths'
free surfaces against each other on the verified scenarios; OUT/tension_length.md the
table. ``off`` runs a case without the tension (``surface_tension.enabled = false``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from common.results import write_results
from common.runs import COLLAPSE_KEYS, run_or_continue, surfaces_m

STRONG = "layer.friction_angle_deg"
# name: (scenario, overrides); "strong-A-M" has the layer at A deg under the 25.5 deg
# column on mesh M, "one-M" is one material on the same mesh and times
CASES: dict[str, tuple[str, list[str]]] = {
    "strong-60-0.04": ("trapezoid-erodible", ["mesh.size=0.04", "time.t_end=0.15",
                                              f"{STRONG}=60"]),
    "one-0.04": ("trapezoid-erodible", ["mesh.size=0.04", "time.t_end=0.15"]),
    "strong-60-0.05": ("trapezoid-erodible", ["mesh.size=0.05", "time.t_end=0.15",
                                              f"{STRONG}=60"]),
    "one-0.05": ("trapezoid-erodible", ["mesh.size=0.05", "time.t_end=0.15"]),
    "strong-45-0.04": ("trapezoid-erodible", ["mesh.size=0.04", "time.t_end=0.15",
                                              f"{STRONG}=45"]),
    "strong-60-0.06": ("trapezoid-erodible", ["mesh.size=0.06", "time.t_end=0.08",
                                              f"{STRONG}=60"]),
    "one-0.06": ("trapezoid-erodible", ["mesh.size=0.06", "time.t_end=0.08"]),
    "trapezoid-erodible": ("trapezoid-erodible", []),
    "cylinder-erodible": ("cylinder-erodible", []),
}
KEYS = [*COLLAPSE_KEYS, "rejections", "surface_tension_steps", "layer_displaced_area_m2",
        "erosion_depth_max_m"]


def one_material(case: str) -> str | None:
    """The one-material case a strong-layer case is compared with."""
    return f"one-{case.rsplit('-', 1)[1]}" if case.startswith("strong-") else None


def table(results: dict) -> str:
    lines = ["| case | length | steps | rejected (error, move) | tension steps | iterations "
             "| over one material | stop (s) | runout (m) | displaced layer (m²) "
             "| over one material |", "|" + "---|" * 11]
    for case, by_length in results["runs"].items():
        for length, row in by_length.items():
            rej = row.get("rejections") or {}
            over = row.get("over_one_material")
            stop = row.get("stop_time_s")
            shifted, ratio = row.get("layer_displaced_area_m2"), row.get("displaced_over_one")
            lines.append(
                f"| {case} | {length} | {row['steps']} | {row['rejected_steps']} "
                f"({rej.get('error', 0)}, {rej.get('move', 0)}) | "
                f"{row.get('surface_tension_steps')} | {row['nonlinear_iterations']:,} | "
                f"{'-' if over is None else f'{over:.1f}'} | "
                f"{'-' if stop is None else f'{stop:.4f}'} | {row['runout_m']:.4f} | "
                f"{'-' if shifted is None else f'{shifted:.3g}'} | "
                f"{'-' if ratio is None else f'{100 * ratio:.0f} %'} |")
    lines += ["", "| scenario | time (s) | free surfaces, local_edge vs mesh_size: mean / max "
              "(mm) |", "|---|---|---|"]
    for case, by_time in results["free_surfaces"].items():
        for t, d in by_time.items():
            lines.append(f"| {case} | {t} | {1e3 * d['mean_m']:.2f} / {1e3 * d['max_m']:.2f} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lengths", nargs="+", default=["mesh_size", "local_edge"],
                        choices=["mesh_size", "local_edge", "off"])
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=CASES)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/tension_length"))
    args = parser.parse_args()
    results: dict = {"command": "python benchmarks/tension_length.py", "runs": {},
                     "free_surfaces": {}}
    for case in args.cases:
        scenario, overrides = CASES[case]
        for length in args.lengths:
            folder = args.out / "runs" / length / case
            tension = ("surface_tension.enabled=false" if length == "off"
                       else f"surface_tension.length={length}")
            summary = run_or_continue(scenario, [*overrides, "output.checkpoint_every=100",
                                                 tension], folder)
            results["runs"].setdefault(case, {})[length] = (
                {k: summary.get(k) for k in KEYS} | {"overrides": overrides})
            print(case, length, summary.get("nonlinear_iterations"), flush=True)
    for case, by_length in results["runs"].items():
        for length, row in by_length.items():
            base = results["runs"].get(one_material(case) or "", {}).get(length)
            if base:
                row["over_one_material"] = (row["nonlinear_iterations"]
                                            / base["nonlinear_iterations"])
                if base.get("layer_displaced_area_m2"):
                    row["displaced_over_one"] = ((row.get("layer_displaced_area_m2") or 0.0)
                                                 / base["layer_displaced_area_m2"])
        if (not one_material(case) and not case.startswith("one-")
                and {"mesh_size", "local_edge"} <= set(by_length)):
            results["free_surfaces"][case] = surfaces_m(
                *(args.out / "runs" / length / case for length in ("mesh_size", "local_edge")))
    write_results(args.out, "tension_length", results, table(results), show=True)


if __name__ == "__main__":
    main()
