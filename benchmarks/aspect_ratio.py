"""Benchmark (issue 16): the built-in `aspect-ratio` study, its runout law and wall time.

Run: python benchmarks/aspect_ratio.py [--workers 2] [--out benchmarks/results/aspect_ratio]
         [--analyse-only]

Runs `granflow sweep aspect-ratio` (rectangles on a rigid bed, l0 = 10 cm, h0/l0 from 0.5
to 4, 8 cells across the smaller side) on a LocalCluster of --workers processes into
OUT/sweep, then writes OUT/aspect_ratio.json and .md (a, normalised runout
(r_inf - l0)/l0, final height h_inf/l0 (the deposit's height at the wall), stop time) with
the least-squares power law (r_inf - l0)/l0 = k a^n over all runs, and OUT/aspect_ratio.png
(log-log) with the exponents measured in two-dimensional channel experiments by Balmforth
and Kerswell (2005, J. Fluid Mech. 538, 399-428): (l_inf - L)/L ~ a^(0.9 +- 0.1) in wide
channels and a^(0.65 +- 0.05) in narrow slots, H/h_inf ~ a^0.6 (wide) and a^0.5 (narrow);
their prefactors depend on the material, so the lines are drawn through our a = 1 point.
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import numpy as np

from granflow.io.run_dir import atomic_file, atomic_write_text
from granflow.sweep import Cluster, load_sweep, run_sweep

WIDTH = 0.1   # l0 of the study (m)
PUBLISHED = {   # Balmforth & Kerswell (2005): exponents of 2D channel collapses
    "runout": [("wide channel, B&K 2005", 0.9), ("narrow slot, B&K 2005", 0.65)],
    "height": [("wide channel, B&K 2005", 1 - 0.6), ("narrow slot, B&K 2005", 1 - 0.5)],
}   # h_inf / l0 = a (h_inf / H) ~ a^(1 - m) when H / h_inf ~ a^m


def analyse(out: Path) -> dict:
    with open(out / "sweep" / "sweep.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh)]
    done = [r for r in rows if r["status"] in ("completed", "stopped")]
    a = np.array([float(r["geometry.height"]) / WIDTH for r in done])
    runout = (np.array([float(r["runout_m"]) for r in done]) - WIDTH) / WIDTH
    height = np.array([float(r["wall_height_m"]) for r in done]) / WIDTH
    order = np.argsort(a)
    a, runout, height = a[order], runout[order], height[order]
    n, log_k = np.polyfit(np.log(a), np.log(runout), 1)
    m, log_c = np.polyfit(np.log(a), np.log(height), 1)
    result = {
        "runs": len(rows), "failed": len(rows) - len(done),
        "a": a.tolist(), "normalised_runout": runout.tolist(), "final_height": height.tolist(),
        "stop_time_s": [float(r["stop_time_s"]) if r["stop_time_s"] else None
                        for r in (done[i] for i in order)],
        "runout_law": {"prefactor": float(np.exp(log_k)), "exponent": float(n)},
        "height_law": {"prefactor": float(np.exp(log_c)), "exponent": float(m)},
    }
    lines = ["| a = h0/l0 | (r_inf - l0)/l0 | h_inf/l0 | stop (s) |", "|---|---|---|---|"]
    lines += [f"| {x:g} | {r:.3f} | {h:.3f} | {s if s is None else f'{s:.3f}'} |"
              for x, r, h, s in zip(a, runout, height, result["stop_time_s"], strict=True)]
    lines.append(f"\nfit: (r_inf - l0)/l0 = {np.exp(log_k):.3f} a^{n:.3f};  "
                 f"h_inf/l0 = {np.exp(log_c):.3f} a^{m:.3f}")
    atomic_write_text(out / "aspect_ratio.md", "\n".join(lines) + "\n")
    atomic_write_text(out / "aspect_ratio.json", json.dumps(result, indent=2))
    plot(out, a, runout, height, (np.exp(log_k), n))
    print("\n".join(lines))
    return result


def plot(out: Path, a: np.ndarray, runout: np.ndarray, height: np.ndarray,
         fit: tuple[float, float]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ref = np.geomspace(a.min(), a.max(), 50)
    anchor_r = np.interp(1.0, a, runout)
    anchor_h = np.interp(1.0, a, height)
    ax1.loglog(a, runout, "ko", label="granflow (rigid bed, 2D)")
    ax1.loglog(ref, fit[0] * ref ** fit[1], "k-", lw=1,
               label=f"fit {fit[0]:.2f} a^{fit[1]:.2f}")
    for (name, exponent), style in zip(PUBLISHED["runout"], ["--", ":"], strict=True):
        ax1.loglog(ref, anchor_r * ref ** exponent, style, label=f"a^{exponent:g} ({name})")
    ax1.set(xlabel="a = h0 / l0", ylabel="(r_inf - l0) / l0", title="Runout")
    ax2.loglog(a, height, "ko", label="granflow")
    for (name, exponent), style in zip(PUBLISHED["height"], ["--", ":"], strict=True):
        ax2.loglog(ref, anchor_h * ref ** exponent, style, label=f"a^{exponent:.1f} ({name})")
    ax2.set(xlabel="a = h0 / l0", ylabel="h_inf / l0", title="Final height (at the wall)")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Rectangular columns, l0 = 10 cm; experimental exponents: Balmforth & "
                 "Kerswell, J. Fluid Mech. 538 (2005)", fontsize=9)
    fig.tight_layout()
    with atomic_file(out / "aspect_ratio.png") as tmp:
        fig.savefig(tmp, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/aspect_ratio"))
    parser.add_argument("--analyse-only", action="store_true")
    args = parser.parse_args()
    if not args.analyse_only:
        sweep = load_sweep("aspect-ratio")
        with Cluster(None, args.workers) as cluster:
            result = run_sweep(sweep, args.out / "sweep", cluster.client, progress=False)
        timing = {"workers": args.workers, "wall_time_s": result.wall_time_s,
                  "runs": len(result.rows), "skipped": result.skipped,
                  "failed": len(result.failed)}
        print(json.dumps(timing))
        atomic_write_text(args.out / f"timing_{args.workers}_workers.json",
                          json.dumps(timing, indent=2))
    analyse(args.out)


if __name__ == "__main__":
    main()
