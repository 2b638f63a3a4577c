"""Convergence of the rigid-bed collapse: default run against a finer mesh and a smaller dt.

Run: python benchmarks/collapse_convergence.py [--out benchmarks/results/collapse]
     (after `collapse_runs.py` (tag paper) and `collapse_study.py fine-mesh fine-dt`)
Reads OUT/{paper, fine-mesh-SHAPE, fine-dt-SHAPE}/SHAPE/ (run directories) and the JSON
summaries; writes OUT/figures/convergence_SHAPE.png (front position, flowing fraction and
kinetic energy against time, the three runs overlaid) and OUT/convergence.md (stop time,
front stop and settle times, runout and runout_1mm of each run, and the change from the
default run).
"""

from __future__ import annotations

import argparse
import csv
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from common.results import write_markdown  # noqa: E402

from granflow.io.plots import save_figure

SHAPES = ["trapezoid-rigid", "rectangle-rigid"]
RUNS = [("paper", "default mesh, dt_max 1e-4"), ("fine-mesh", "mesh size / 2"),
        ("fine-dt", "dt_max 1e-5")]
FIGURES = ["stop_time_s", "front_stop_time_s", "front_settle_time_s", "runout_m",
           "runout_1mm_m"]


def summary(out: Path, tag: str, shape: str) -> dict | None:
    """The JSON record of one run: OUT/TAG.json or OUT/TAG-SHAPE.json."""
    for name in (f"{tag}.json", f"{tag}-{shape}.json"):
        path = out / name
        if path.exists() and shape in (data := json.loads(path.read_text())):
            return data[shape]
    return None


def history(out: Path, tag: str, shape: str) -> dict[str, np.ndarray] | None:
    for run in (out / tag / shape, out / f"{tag}-{shape}" / shape):
        path = run / "diagnostics.csv"
        if path.exists():
            with open(path) as fh:
                rows = list(csv.DictReader(fh))
            return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
    return None


def difference(value: float | None, reference: float | None) -> float | None:
    return None if value is None or reference is None else value - reference


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/collapse"))
    out = parser.parse_args().out
    lines = ["| shape | run | " + " | ".join(FIGURES) + " | change from default (s, s, s, m, m) |",
             "|---|---|" + "---|" * (len(FIGURES) + 1)]
    for shape in SHAPES:
        fig, axes = plt.subplots(1, 3, figsize=(14, 3.6))
        base = None
        for k, (tag, label) in enumerate(RUNS):
            record, h = summary(out, tag, shape), history(out, tag, shape)
            if k == 0:
                base = record
            if record is not None:
                values = [record.get(f) for f in FIGURES]
                change = [difference(record.get(f), (base or {}).get(f)) for f in FIGURES]
                lines.append(f"| {shape} | {label} | " + " | ".join(
                    "-" if v is None else f"{v:.4g}" for v in values) + " | " + ", ".join(
                    "-" if c is None else f"{c:+.3f}" for c in change) + " |")
            if h is None:
                continue
            style = {"color": f"C{k}", "lw": 3.0 if k == 0 else 1.2, "label": label}
            axes[0].plot(h["t"], h["front_x"], **style)
            axes[1].plot(h["t"], h["flowing_fraction"], **style)
            axes[2].semilogy(h["t"], np.maximum(h["kinetic_energy"], 1e-12), **style)
        for ax, ylabel in zip(axes, ["front X (m)", "flowing fraction (|u| > 1 mm/s)",
                                     "kinetic energy (J/m)"], strict=True):
            ax.set(xlabel="t (s)", ylabel=ylabel)
        axes[0].set_title(shape)
        axes[0].legend(fontsize=8)
        (out / "figures").mkdir(exist_ok=True)
        save_figure(fig, out / "figures" / f"convergence_{shape}.png", dpi=120)
        plt.close(fig)
    write_markdown(out / "convergence.md", lines, show=True)


if __name__ == "__main__":
    main()
