"""The figures of a 3D column (``plots/``), drawn from its files: the free surfaces along
the channel's centre line and against its side wall at the output times and at the end
(``free_surfaces``), and the front and the kinetic energy against time (``history``)."""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from granflow.io import profiles  # noqa: E402
from granflow.io.diagnostics import read_diagnostics  # noqa: E402
from granflow.io.plots import FigureFormat  # noqa: E402
from granflow.io.run_dir import RunDir  # noqa: E402

PLACES = (("free_surface", "centre line"), ("free_surface_wall", "side wall"))


def plot_channel(run_dir: RunDir, config: Any) -> None:
    """Both figures, each drawn only from what the run directory holds."""
    fmt = FigureFormat.of(config)
    root = run_dir.root
    found = {kind: profiles.list_profiles(root, kind) for kind, _ in PLACES}
    if any(found.values()):
        fig, axes = plt.subplots(2, 1, figsize=(7, 6), sharex=True, sharey=True)
        for ax, (kind, place) in zip(axes, PLACES, strict=True):
            for item in found[kind]:
                data = item.read()
                final = item.label == profiles.FINAL
                ax.plot(data["x"], data["z"], "k-" if final else "-", lw=1.3 if final else 1,
                        label="final" if final else f"t = {item.t:.2f} s")
            ax.set_title(f"free surface, {place}")
            ax.set_ylabel("Z (m)")
            ax.set_aspect("equal")
            ax.legend(fontsize=7, loc="upper right")
        axes[-1].set_xlabel("X (m)")
        fmt.save(fig, run_dir, "free_surfaces")
    diagnostics = read_diagnostics(root)
    if len(diagnostics):
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6, 5), sharex=True)
        a1.plot(diagnostics["t"], diagnostics["front_x"], label="furthest point")
        for column, label in (("front_x_centre", "centre line"), ("front_x_side", "side wall")):
            if column in diagnostics:
                a1.plot(diagnostics["t"], diagnostics[column], "--", label=label)
        a1.set_ylabel("front X (m)")
        a1.legend(fontsize=8)
        a2.plot(diagnostics["t"], diagnostics["kinetic_energy"])
        a2.set_ylabel("kinetic energy (J)")
        a2.set_xlabel("t (s)")
        fmt.save(fig, run_dir, "history")
