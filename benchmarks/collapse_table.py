"""Tabulate the finished collapse benchmarks and draw the (3.6)/(3.7) comparison.

Run: python benchmarks/collapse_table.py   (after collapse_runs.py / collapse_study.py)
Prints a markdown table of every variant's OUT/TAG.json (figures as the runs recorded them
in their summaries) and writes OUT/table.md, OUT/comparison.json and, when the s52-* run
directories are there, OUT/figures/mesh_velocity_comparison.png (free surfaces of (3.6) and
(3.7) at the output times).
"""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from common.results import write_json, write_markdown  # noqa: E402

from granflow.io import profiles  # noqa: E402
from granflow.io.plots import save_figure

OUT = Path("benchmarks/results/collapse")
COLUMNS = ["status", "stop_time_s", "front_stop_time_s", "front_settle_time_s", "runout_m",
           "wall_height_m",
           "volume_relative_error", "n_triangles", "remeshes", "steps", "linear_solves",
           "wall_time_s", "runout_1mm_m", "surface_edge_spread"]


def surface(run: Path, t: float) -> np.ndarray | None:
    """The free surface the run wrote at output time t (None if it did not)."""
    return profiles.curves(run, "free_surface", [t]).get(t)


def variant_records() -> dict[str, dict[str, dict]]:
    """OUT/TAG.json of every variant run (``collapse_runs.py``, ``collapse_study.py``): a
    summary's figures per scenario; other records in OUT (comparisons, checks) are not."""
    found = {}
    for path in sorted(OUT.glob("*.json")):
        data = json.loads(path.read_text())
        if isinstance(data, dict) and data and all(
                isinstance(r, dict) and "status" in r for r in data.values()):
            found[path.stem] = data
    return found


def main() -> None:
    rows = [{"variant": tag, "scenario": scenario, **{c: r.get(c) for c in COLUMNS}}
            for tag, record in variant_records().items() for scenario, r in record.items()]
    head = ["variant", "scenario", *COLUMNS]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        lines.append("| " + " | ".join(
            f"{r[c]:.4g}" if isinstance(r[c], float) else str(r[c]) for c in head) + " |")
    write_markdown(OUT / "table.md", lines, show=True)
    write_json(OUT / "comparison.json", rows)
    pairs = [("s52-elastic", "s52-lagrange", "default mesh"),
             ("s52-elastic-fine", "s52-lagrange-fine", "half mesh size")]
    shapes = {"trapezoid-rigid": [0.18, 0.3, 0.48, 0.66, 0.78, 1.02],
              "rectangle-rigid": [0.18, 0.3, 0.42, 0.5, 0.78, 1.06]}
    fig, axes = plt.subplots(len(shapes), len(pairs), figsize=(12, 6), squeeze=False)
    drawn = False
    for i, (shape, times) in enumerate(shapes.items()):
        for j, (elastic, lagrange, label) in enumerate(pairs):
            ax = axes[i][j]
            for k, t in enumerate(times):
                for tag, style in ((elastic, "-"), (lagrange, "--")):
                    run = OUT / tag / shape
                    if not run.exists():
                        run = OUT / f"{tag}-{shape}" / shape
                    xz = surface(run, t)
                    if xz is not None:
                        drawn = True
                        ax.plot(xz[:, 0], xz[:, 1], style, color=f"C{k}", lw=1,
                                label=f"{t:.2f} s" if style == "-" else None)
            ax.set(title=f"{shape}, {label}: (3.6) solid, (3.7) dashed", aspect="equal",
                   xlabel="X (m)", ylabel="Z (m)")
    if not drawn:      # the run directories are not here (not committed): keep the figure
        print("no (3.6)/(3.7) runs in", OUT, "- figure not redrawn")
        return
    axes[0][0].legend(fontsize=7)
    (OUT / "figures").mkdir(exist_ok=True)
    save_figure(fig, OUT / "figures" / "mesh_velocity_comparison.png", dpi=120)


if __name__ == "__main__":
    main()
