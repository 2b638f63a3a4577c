"""The slab's figure (``scenarios/slab.py``), from its run's files alone: the slab's and
the layer's mean speeds and the bed's slip against time, and the velocity and the
displacement across the strip at the output times and at the end."""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from granflow.io import profiles  # noqa: E402
from granflow.io.diagnostics import read_diagnostics  # noqa: E402
from granflow.io.plots import FigureFormat  # noqa: E402
from granflow.io.run_dir import RunDir  # noqa: E402

SPEEDS = {"slab_speed": "slab", "layer_speed": "layer", "bed_slip": "bed slip",
          "surface_speed": "surface"}


def plot_slab(run_dir: RunDir, config: Any) -> None:
    """plots/slab: nothing before the first step is written."""
    table = read_diagnostics(run_dir.root)
    if not len(table) or "slab_speed" not in table:
        return
    fig, (speeds, across, moved) = plt.subplots(1, 3, figsize=(12, 3.6))
    for column, label in SPEEDS.items():
        if column == "layer_speed" and not config.geometry.erodible_thickness:
            continue
        speeds.plot(table["t"], table[column], label=label)
    speeds.set(xlabel="t (s)", ylabel="mean u along the bed (m/s)")
    speeds.legend(fontsize=8)
    for found in profiles.list_profiles(run_dir.root, "slab"):
        data = found.read()
        label = "end" if found.final else f"t = {found.t:g} s"
        across.plot(data["u_x"], 1e3 * data["z"], ".-", label=label)
        moved.plot(1e3 * data["displacement"], 1e3 * data["z"], ".-", label=label)
    for ax, what in ((across, "u (m/s)"), (moved, "displacement (mm)")):
        if config.geometry.erodible_thickness:
            ax.axhline(1e3 * config.geometry.erodible_thickness, color="0.6", lw=0.8)
        ax.set(xlabel=what, ylabel="z (mm)")
    across.legend(fontsize=8)
    FigureFormat.of(config).save(fig, run_dir, "slab")
