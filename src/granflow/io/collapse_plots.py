"""Figures of a collapse run, like the paper's (Figures 7-9, 12-15), and an animation."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from granflow.geometry.domains import column  # noqa: E402
from granflow.io import profiles  # noqa: E402
from granflow.io.diagnostics import read_diagnostics  # noqa: E402
from granflow.io.erosion_plots import plot_erosion  # noqa: E402
from granflow.io.frames import read_frames  # noqa: E402
from granflow.io.plots import save_figure  # noqa: E402
from granflow.io.run_dir import RunDir  # noqa: E402


def _profiles(run_dir: RunDir, kind: str, times: list[float]) -> list[tuple[float, dict]]:
    """The profiles of ``kind`` at those of ``times`` that were written."""
    out = []
    for t in times:
        found = profiles.profile_at(run_dir.root, kind, t)
        if found is not None:
            out.append((t, found))
    return out


def _label(t: float, summary: dict[str, Any], prefix: str = "t = ") -> str:
    """An output time's legend entry; "(rest state)" when it was written from the state at
    rest because the run stopped before it (summary.json's outputs_at_rest)."""
    rest = any(abs(t - x) < 1e-9 for x in summary.get("outputs_at_rest") or [])
    return f"{prefix}{t:.2f} s" + (" (rest state)" if rest else "")


def _final_surface(run_dir: RunDir, summary: dict[str, Any]) -> tuple[str, dict] | None:
    """The last state's free surface (its final profile) and its legend label:
    "at rest" when the run stopped by the rest rule, else the run's status."""
    surface = profiles.final_profile(run_dir.root, "free_surface")
    t = summary.get("final_profiles_t")
    if surface is None or t is None:
        return None
    what = "at rest" if summary.get("status") == "stopped" else summary.get("status", "end")
    return f"{what}, t = {t:.2f} s", surface


def initial_outline(config: Any) -> np.ndarray:
    """The column at t = 0 as a closed polyline (drawn dashed for reference)."""
    g = config.geometry
    poly = column(g.shape, g.width, g.height, g.front_angle_deg, g.erodible_thickness,
                  g.bed_length)
    points = np.asarray(poly.points, dtype=float)
    return np.vstack([points, points[:1]])


def plot_collapse(run_dir: RunDir, config: Any) -> None:
    """Free surfaces, interfaces, velocity sections, front/energy history and a GIF, from
    the run directory's files alone, through their readers (profiles, diagnostics, frames)."""
    summary = RunDir.summary(run_dir.root)
    final = _final_surface(run_dir, summary)
    # output times after the mass came to rest hold the rest state: drawn once, as "at rest"
    rest = summary.get("outputs_at_rest") or [] if final is not None else []
    times = [t for t in config.time.output_times if not any(abs(t - x) < 1e-9 for x in rest)]
    height = config.geometry.height
    bed = _bed_note(config.geometry.slope_deg, config.geometry.axisymmetric)
    x = "r" if config.geometry.axisymmetric else "x"     # the radius of a cylinder
    outline = initial_outline(config)
    fig, ax = plt.subplots(figsize=(8, 3))
    ax.plot(*outline.T, "--", color="0.6", lw=0.8, label="t = 0")
    for t, prof in _profiles(run_dir, "free_surface", times):
        ax.plot(prof["x"], prof["z"], label=_label(t, summary))
    if final is not None:
        ax.plot(final[1]["x"], final[1]["z"], color="k", lw=1.2, label=final[0])
    ax.set(xlabel=f"{x} (m)", ylabel="z (m)", title=f"Free surface{bed}",
           aspect=_aspect(ax, height))
    _legend(ax)
    save_figure(fig, run_dir.path("plots/free_surface.png"))

    fig, ax = plt.subplots(figsize=(8, 3))
    ax.plot(*outline.T, "--", color="0.6", lw=0.8, label="t = 0")
    for t, prof in _profiles(run_dir, "interface", times):
        line, = ax.plot(prof["x"], prof["z"], label=_label(t, summary))
        surf = _profiles(run_dir, "free_surface", [t])
        if surf:
            ax.plot(surf[0][1]["x"], surf[0][1]["z"], ":", color=line.get_color(), lw=0.8)
    ax.set(xlabel=f"{x} (m)", ylabel="z (m)", aspect=_aspect(ax, height),
           title="Static/flowing interface: edges of the cells with |u| > 1 mm/s (steps "
                 f"of one cell){bed}; dotted: free surface")
    _legend(ax)
    save_figure(fig, run_dir.path("plots/interface.png"))

    sections = _profiles(run_dir, "velocity_sections", times)
    if sections:
        offsets = sorted({round(x, 6) for _, p in sections if p for x in p["section_x"]})
        fig, axes = plt.subplots(2, len(offsets), figsize=(3.2 * len(offsets), 6),
                                 squeeze=False, sharey=True)
        for j, xs in enumerate(offsets):
            for t, p in sections:
                if not p:
                    continue
                m = np.isclose(p["section_x"], xs)
                axes[0][j].plot(p["u_x"][m], p["z"][m], label=_label(t, summary, ""))
                axes[1][j].plot(p["u_z"][m], p["z"][m])
            axes[0][j].set_title(f"section {x} = {xs:.3f} m")
            axes[0][j].set_xlabel(f"u_{x} (m/s)")
            axes[1][j].set_xlabel("u_z (m/s)")
        axes[0][0].set_ylabel("z (m)")
        axes[1][0].set_ylabel("z (m)")
        fig.suptitle(f"Velocity profiles across vertical sections{bed}", fontsize=10)
        for a in axes.flat:
            a.xaxis.set_major_locator(plt.MaxNLocator(4))
        _legend(axes[0][0])
        save_figure(fig, run_dir.path("plots/velocity_sections.png"))

    diag = read_diagnostics(run_dir.root)
    if len(diag):
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.2))
        a1.plot(diag["t"], diag["front_x"])
        a1.set(xlabel="t (s)", ylabel=f"front {x} (m)", title=f"Front position{bed}")
        a2.plot(diag["t"], diag["kinetic_energy"])
        energy = "J" if config.geometry.axisymmetric else "J/m"   # whole body, or per metre
        a2.set(xlabel="t (s)", ylabel=f"kinetic energy ({energy})", title="Kinetic energy")
        save_figure(fig, run_dir.path("plots/front_and_energy.png"))

    if config.geometry.erodible_thickness > 0:
        plot_erosion(run_dir, config)

    frames = read_frames(run_dir.root)
    if frames:
        _animate(run_dir.path("plots/speed.gif"), frames, outline, height, bed, x)


def _bed_note(slope_deg: float, axisymmetric: bool = False) -> str:
    """Words for a title: x runs along the bed, which is inclined on a slope; or the
    section of a cylinder, r from its axis."""
    if axisymmetric:
        return " (axisymmetric: r from the axis)"
    return f" (x along the bed, inclined at {slope_deg:g}°)" if slope_deg else ""


def _aspect(ax: plt.Axes, height: float) -> str:
    """True proportions, unless the flow ran out over more than 8 column heights (a slope):
    then a stretched Z, or the deposit would be a line."""
    xmin, xmax = ax.dataLim.intervalx
    return "equal" if xmax - xmin <= 8 * height else "auto"


def _legend(ax: plt.Axes) -> None:
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)


def _animate(path: Path, frames: list[dict[str, Any]], outline: np.ndarray,
             height: float, bed: str = "", x: str = "x") -> None:
    """The GIF of the cell speeds: axes, ticks and outline are drawn once; each frame
    redraws only its mesh colours, interface and title over that background (blitting)
    and goes to Pillow as it is: a fifth of the time of redrawing whole figures."""
    xmax = max(f["xy"][:, 0].max() for f in frames) * 1.02
    vmax = max(float(f["speed"].max()) for f in frames) or 1.0
    fig, ax = plt.subplots(figsize=(8.6, 3.0))
    ax.plot(*outline.T, "--", color="0.6", lw=0.8)
    ax.set(xlim=(0, xmax), ylim=(0, height * 1.05), aspect="equal", xlabel=f"{x} (m)",
           ylabel="z (m)")
    scale = plt.cm.ScalarMappable(norm=plt.Normalize(0, vmax), cmap="viridis")
    fig.colorbar(scale, ax=ax, label="speed |u| (m/s)", fraction=0.025, pad=0.02)
    title = ax.set_title(" " * 80)
    fig.tight_layout()
    fig.canvas.draw()
    title.set_animated(True)
    background = fig.canvas.copy_from_bbox(fig.bbox)
    images = []
    for f in frames:
        fig.canvas.restore_region(background)
        cells = ax.tripcolor(f["xy"][:, 0], f["xy"][:, 1], f["tri"], facecolors=f["speed"],
                             vmin=0, vmax=vmax, cmap="viridis", edgecolors="none",
                             animated=True)
        line, = ax.plot(f["interface"][:, 0], f["interface"][:, 1], "r-", lw=1,
                        animated=True)
        title.set_text(f"t = {f['t']:.3f} s; red: static/flowing interface{bed}")
        for artist in (cells, line, title):
            ax.draw_artist(artist)
        rgba = np.asarray(fig.canvas.buffer_rgba())
        images.append(Image.fromarray(rgba[..., :3].copy()))
        cells.remove()
        line.remove()
    plt.close(fig)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.tmp.gif")
    images[0].save(tmp, save_all=True, append_images=images[1:], duration=100, loop=0)
    tmp.replace(path)
