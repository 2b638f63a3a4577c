"""Benchmark: a built-in aspect-ratio study, its runout law and wall time.

Run: python benchmarks/aspect_ratio.py [--study aspect-ratio] [--workers 2]
         [--out benchmarks/results/aspect_ratio] [--analyse-only]

Runs `granflow sweep STUDY` (rectangles, l0 = 10 cm, h0/l0 from 0.5 to 4, 8 cells across
the smaller side; `aspect-ratio` on the rigid bed, `aspect-ratio-slope10` on a 10 deg bed,
`aspect-ratio-erodible` over a 5 mm layer, a = column height above the layer / l0,
`aspect-ratio-mu-i` the rigid bed with mu(I), `aspect-ratio-glass-beads` and
`aspect-ratio-hysteretic` with the slope study's glass beads, one friction or starting
harder than they flow) on a
LocalCluster of --workers processes into OUT/sweep, then writes OUT/aspect_ratio.json and
.md (a, normalised runout (r_inf - l0)/l0, final height h_inf/l0 (the deposit's height at
the wall, above the layer), stop time) with the least-squares power law
(r_inf - l0)/l0 = k a^n over all runs and over a >= 2, and OUT/aspect_ratio.png (log-log)
with the published laws of two-dimensional channel collapses:

- Lube et al. (2005, Phys. Rev. E 72, 041301), sand, rice, sugar:
  (r_inf - l0)/l0 = 1.2 a for a < 1.8 and 1.9 a^(2/3) for a > 2.8;
  h_inf/l0 = a for a < 1.15 and a^0.4 above;
- Lajeunesse et al. (2005, Phys. Fluids 17, 103302), glass beads:
  (r_inf - l0)/l0 = 1.8 a for a < 3 and 2.3 a^(2/3) above;
  both as consolidated by Lagree, Staron and Popinet (2011, J. Fluid Mech. 686, 378-408,
  eqs. (3.1)-(3.2)); the original papers were not read here;
- Balmforth and Kerswell (2005, J. Fluid Mech. 538, 399-428): (l_inf - L)/L ~ a^(0.9 +- 0.1)
  in wide channels and a^(0.65 +- 0.05) in narrow slots, H/h_inf ~ a^0.6 (wide) and a^0.5
  (narrow); their prefactors depend on the material, so these lines go through our a = 1.
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np
from common.fits import power_fit
from common.results import write_json, write_markdown
from common.studies import run_study

from granflow.io.run_dir import atomic_file
from granflow.sweep import load_sweep

WIDTH = 0.1   # l0 of the studies (m)
LAWS = {   # name: (linear prefactor, linear up to, power prefactor, power from), exponent 2/3
    "Lube et al. 2005": (1.2, 1.8, 1.9, 2.8),
    "Lajeunesse et al. 2005": (1.8, 3.0, 2.3, 3.0),
}
PUBLISHED = {   # Balmforth & Kerswell (2005): exponents of 2D channel collapses
    "runout": [("wide channel, B&K 2005", 0.9), ("narrow slot, B&K 2005", 0.65)],
    "height": [("wide channel, B&K 2005", 1 - 0.6), ("narrow slot, B&K 2005", 1 - 0.5)],
}   # h_inf / l0 = a (h_inf / H) ~ a^(1 - m) when H / h_inf ~ a^m


def published_runout(law: str, a: np.ndarray) -> np.ndarray:
    """(r_inf - l0)/l0 of a published law; NaN in its transition gap (no fit there)."""
    k1, a1, k2, a2 = LAWS[law]
    return np.where(a <= a1, k1 * a, np.where(a >= a2, k2 * a ** (2 / 3), np.nan))


def lube_height(a: np.ndarray) -> np.ndarray:
    """h_inf/l0 of Lube et al. (2005): a below a = 1.15 (the top stays), a^0.4 above."""
    return np.where(a < 1.15, a, a ** 0.4)


def analyse(out: Path, study: str) -> dict:
    fixed = dict(item.split("=", 1) for item in load_sweep(study).fixed)
    layer = float(fixed.get("geometry.erodible_thickness", 0.0))
    with open(out / "sweep" / "sweep.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh)]
    done = [r for r in rows if r["status"] in ("completed", "stopped")]
    a = np.array([(float(r["geometry.height"]) - layer) / WIDTH for r in done])
    runout = (np.array([float(r["runout_m"]) for r in done]) - WIDTH) / WIDTH
    height = (np.array([float(r["wall_height_m"]) for r in done]) - layer) / WIDTH
    stop = [float(r["stop_time_s"]) if r["stop_time_s"] else None for r in done]
    order = np.argsort(a)
    a, runout, height = a[order], runout[order], height[order]
    stop = [stop[i] for i in order]
    tall = a >= 2
    fits = {"runout_all": power_fit(a, runout), "height_all": power_fit(a, height)}
    if tall.sum() >= 2:
        fits["runout_a>=2"] = power_fit(a[tall], runout[tall])
    if (a >= 1).sum() >= 2:
        fits["height_a>=1"] = power_fit(a[a >= 1], height[a >= 1])
    result = {
        "study": study, "runs": len(rows), "failed": len(rows) - len(done),
        "statuses": sorted({r["status"] for r in rows}),
        "a": a.tolist(), "normalised_runout": runout.tolist(), "final_height": height.tolist(),
        "stop_time_s": stop,
        "fits": {k: {"prefactor": v[0], "exponent": v[1]} for k, v in fits.items()},
        "published_runout": {law: published_runout(law, a).tolist() for law in LAWS},
        "lube_height": lube_height(a).tolist(),
    }
    fmt = lambda x: "-" if x is None or not np.isfinite(x) else f"{x:.3f}"  # noqa: E731
    lines = [f"Study `{study}`: {len(done)} of {len(rows)} runs finished.", "",
             "| a = h0/l0 | (r_inf - l0)/l0 | Lube 2005 | Lajeunesse 2005 | h_inf/l0 "
             "| Lube 2005 | stop (s) |", "|---|---|---|---|---|---|---|"]
    lube, lajeunesse = (published_runout(law, a) for law in LAWS)
    lines += [f"| {x:g} | {r:.3f} | {fmt(lu)} | {fmt(la)} | {h:.3f} | {fmt(lh)} | {fmt(t)} |"
              for x, r, lu, la, h, lh, t in zip(a, runout, lube, lajeunesse, height,
                                               lube_height(a), stop, strict=True)]
    lines.append("")
    lines += [f"fit {name}: {k:.3f} a^{n:.3f}" for name, (k, n) in fits.items()]
    write_markdown(out / "aspect_ratio.md", lines, show=True)
    write_json(out / "aspect_ratio.json", result)
    plot(out, study, a, runout, height, fits["runout_all"])
    return result


def plot(out: Path, study: str, a: np.ndarray, runout: np.ndarray, height: np.ndarray,
         fit: tuple[float, float]) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    ref = np.geomspace(min(a.min(), 0.5), max(a.max(), 4.0), 200)
    anchor_r = np.interp(1.0, a, runout)
    anchor_h = np.interp(1.0, a, height)
    ax1.loglog(a, runout, "ko", label=f"granflow ({study})")
    ax1.loglog(ref, fit[0] * ref ** fit[1], "k-", lw=1,
               label=f"fit {fit[0]:.2f} a^{fit[1]:.2f}")
    for law, color in zip(LAWS, ["tab:blue", "tab:red"], strict=True):
        ax1.loglog(ref, published_runout(law, ref), "-", color=color, lw=1.5, label=law)
    for (name, exponent), style in zip(PUBLISHED["runout"], ["--", ":"], strict=True):
        ax1.loglog(ref, anchor_r * ref ** exponent, style, color="grey",
                   label=f"a^{exponent:g} ({name}, through our a = 1)")
    ax1.set(xlabel="a = h0 / l0", ylabel="(r_inf - l0) / l0", title="Runout")
    ax2.loglog(a, height, "ko", label="granflow")
    ax2.loglog(ref, lube_height(ref), "-", color="tab:blue", lw=1.5, label="Lube et al. 2005")
    for (name, exponent), style in zip(PUBLISHED["height"], ["--", ":"], strict=True):
        ax2.loglog(ref, anchor_h * ref ** exponent, style, color="grey",
                   label=f"a^{exponent:.1f} ({name}, through our a = 1)")
    ax2.set(xlabel="a = h0 / l0", ylabel="h_inf / l0", title="Final height (at the wall)")
    for ax in (ax1, ax2):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Rectangular columns, l0 = 10 cm. Laws of 2D channel experiments: Lube et al., "
                 "Phys. Rev. E 72 (2005); Lajeunesse et al., Phys. Fluids 17 (2005) (as in "
                 "Lagree et al., JFM 686 (2011), eq. 3.1-3.2);\nBalmforth & Kerswell, JFM 538 "
                 "(2005) (exponents only)", fontsize=8)
    fig.tight_layout()
    with atomic_file(out / "aspect_ratio.png") as tmp:
        fig.savefig(tmp, dpi=120)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--study", default="aspect-ratio",
                        choices=["aspect-ratio", "aspect-ratio-slope10", "aspect-ratio-erodible",
                                 "aspect-ratio-mu-i", "aspect-ratio-glass-beads",
                                 "aspect-ratio-hysteretic"])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=None,
                        help="default benchmarks/results/<study with _ for ->")
    parser.add_argument("--analyse-only", action="store_true")
    args = parser.parse_args()
    args.out = args.out or Path("benchmarks/results") / args.study.replace("-", "_")
    if not args.analyse_only:
        run_study(args.study, args.out, args.workers)
    analyse(args.out, args.study)


if __name__ == "__main__":
    main()
