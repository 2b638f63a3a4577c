"""Matplotlib figures of a run (headless), and how they are written: PNG, PDF or SVG at the
configured resolution (``output.figure_format``, ``output.dpi``)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from granflow.io import profiles  # noqa: E402
from granflow.io.run_dir import RunDir, RunDirError, atomic_file  # noqa: E402


@dataclass(frozen=True)
class FigureFormat:
    """How a run's figures are written: ``plots/NAME.SUFFIX``, rasters at ``dpi``."""

    suffix: str = "png"
    dpi: int = 150

    @classmethod
    def of(cls, config: Any) -> FigureFormat:
        """The format a configuration asks for ([output] figure_format and dpi)."""
        return cls(config.output.figure_format, config.output.dpi)

    def path(self, run_dir: RunDir, name: str) -> Path:
        return run_dir.path(f"plots/{name}.{self.suffix}")

    def save(self, fig: plt.Figure, run_dir: RunDir, name: str) -> Path:
        """``fig`` as plots/NAME in this format; returns the file."""
        path = self.path(run_dir, name)
        save_figure(fig, path, dpi=self.dpi)
        return path


def save_figure(fig: plt.Figure, path: Path, dpi: int = 150, **kwargs: object) -> None:
    """Save ``fig`` to ``path`` (its suffix gives the format) atomically, through a fresh
    temporary file renamed over it (a killed run leaves no half image; no existing name or
    link is written through), and close it. ``kwargs`` go to ``savefig``."""
    with atomic_file(Path(path)) as tmp:
        fig.savefig(tmp, dpi=dpi, **({"bbox_inches": "tight"} | kwargs))
    plt.close(fig)


def plot_plug_profile(path: Path, z: np.ndarray, u: np.ndarray, reference: np.ndarray,
                      t: float, dpi: int = 150) -> None:
    """The 2D velocity along a vertical against the 1D reference of (4.1)."""
    fig, ax = plt.subplots(figsize=(4.5, 5))
    ax.plot(reference, z, "k-", lw=2, label="1D reference (4.1)")
    ax.plot(u, z, "r--", lw=1.5, label="granflow 2D")
    ax.set_xlabel("U (m/s)")
    ax.set_ylabel("Z (m)")
    ax.set_title(f"Plug flow, t = {t:.3f} s")
    ax.legend(loc="upper left")
    save_figure(fig, path, dpi=dpi)


def plot_plug_flow(run_dir: RunDir, config: Any) -> None:
    """The periodic layer's figure: the velocity profile against the 1D reference, of the
    last accepted state, or of the last output time on disk for a run still going."""
    found = profiles.list_profiles(run_dir.root, "velocity")
    final_t = RunDir.summary(run_dir.root).get("final_profiles_t")
    found = [p for p in found if p.t is not None or (p.final and final_t is not None)]
    if not found:
        raise RunDirError(f"'{run_dir.root}' holds no velocity profile yet (profiles/ is "
                          "written at time.output_times)")
    last = found[-1]
    data = last.read()
    t = last.t if last.t is not None else float(final_t)
    fmt = FigureFormat.of(config)
    plot_plug_profile(fmt.path(run_dir, "velocity_profile"), data["z"], data["u_x"],
                      data["u_reference"], t, dpi=fmt.dpi)


def plot_convergence_table(path: Path, results: list, table: int) -> None:
    """Log-log error against dt, one line per dZ; the paper's values dashed."""
    eps_values = sorted({r.eps for r in results}, reverse=True)
    fig, axes = plt.subplots(1, len(eps_values), figsize=(4.2 * len(eps_values), 3.8),
                             squeeze=False, sharey=True)
    for ax, eps in zip(axes[0], eps_values, strict=True):
        cells = [r for r in results if r.eps == eps]
        for i, dz in enumerate(sorted({r.dZ for r in cells}, reverse=True)):
            rows = sorted((r for r in cells if r.dZ == dz), key=lambda r: r.dt)
            color = f"C{i}"
            dts = [r.dt for r in rows]
            ax.loglog(dts, [r.error for r in rows], "o-", color=color, label=f"dZ={dz:g} m")
            ax.loglog(dts, [r.paper_error for r in rows], "s--", color=color, alpha=0.6,
                      mfc="none")
        ax.set_xlabel("dt (s)")
        ax.set_title(f"Table {table}, eps = {eps:g} 1/s")
        ax.grid(True, which="both", alpha=0.3)
    axes[0][0].set_ylabel("relative L2 error of u at T")
    axes[0][0].legend(title="solid: granflow\ndashed: paper", fontsize=8)
    save_figure(fig, path)


def plot_level_differences(path: Path, series: dict[str, list[float | None]],
                           tolerances: dict[str, float], title: str) -> None:
    """``granflow converge``: the change of each quantity from one level to the next on a
    log axis, one line per quantity, its tolerance dotted in the same colour (a missing or
    zero change leaves a gap; a quantity with none is not drawn)."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for i, (name, values) in enumerate(series.items()):
        x = np.arange(1, len(values) + 1)
        y = np.array([np.nan if v is None or v <= 0 else v for v in values], dtype=float)
        color = f"C{i}"
        if np.isfinite(y).any():
            ax.semilogy(x, y, "o-", color=color, label=name)
            if name in tolerances:
                ax.axhline(tolerances[name], color=color, ls=":", lw=1)
        ax.set_xticks(x, [f"{k - 1}-{k}" for k in x])
    ax.set_xlabel("levels compared")
    ax.set_ylabel("|change| (dotted: tolerance)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save_figure(fig, path)
