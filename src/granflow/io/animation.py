"""The animation of a collapse, ``plots/speed.gif``, from its frames on disk
(``io/frames.py``): the speed of the P2 velocity at the vertices, shaded smoothly across
each triangle (Gouraud), cropped to where the material went, with the time, a colour bar
and the static/flowing interface (the 1 mm/s contour of the same speeds)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri as mtri  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

from granflow.io.run_dir import atomic_file  # noqa: E402
from granflow.simulation.rest import FLOWING_SPEED  # noqa: E402

FRAME_MS = 100         # display time of a frame (0.02 s of flow: a fifth of real time)
WIDTH_IN = 8.0         # figure width (inches); the height follows the cropped extent
MAX_DPI = 110          # a GIF beyond this only grows (880 pixels wide)
COLOURS = 64           # palette of a frame: smooth shading without dithering noise


def vertex_speed(frame: dict[str, Any]) -> np.ndarray:
    """The frame's speed at the vertices: stored since frames carried it; for older frames,
    the area-weighted mean of the cell speeds around each vertex."""
    if "vertex_speed" in frame:
        return np.asarray(frame["vertex_speed"], dtype=float)
    xy, tri, cells = frame["xy"], frame["tri"], np.asarray(frame["speed"], dtype=float)
    a, b, c = (xy[tri[:, i]] for i in range(3))
    area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                        - (c[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))
    total, weight = np.zeros(len(xy)), np.zeros(len(xy))
    for i in range(3):
        np.add.at(total, tri[:, i], area * cells)
        np.add.at(weight, tri[:, i], area)
    return total / np.maximum(weight, 1e-300)


def extent(frames: list[dict[str, Any]], layer: float) -> tuple[float, float]:
    """(x, z) limits holding the material above an erodible layer of thickness ``layer`` in
    every frame (the resting layer beyond the flow is left out), with a margin."""
    xmax, zmax = 0.0, 0.0
    for f in frames:
        xy = f["xy"]
        above = xy[:, 1] > 1.2 * layer + 1e-3 if layer > 0 else np.ones(len(xy), bool)
        moving = vertex_speed(f) > FLOWING_SPEED
        keep = above | moving
        xmax = max(xmax, float(xy[keep, 0].max()) if keep.any() else float(xy[:, 0].max()))
        zmax = max(zmax, float(xy[:, 1].max()))
    return 1.04 * xmax, 1.06 * zmax


def animate(path: Path, frames: list[dict[str, Any]], outline: np.ndarray, layer: float = 0.0,
            note: str = "", x: str = "x", dpi: int = MAX_DPI) -> None:
    """Write the GIF. Axes, colour bar and the initial outline are drawn once; each frame
    redraws only its shading, interface and time over that background (blitting)."""
    xmax, zmax = extent(frames, layer)
    vmax = max(float(vertex_speed(f).max()) for f in frames) or 1.0
    height = max(1.6, min(WIDTH_IN * zmax / xmax * 0.9 + 0.9, 6.0))
    fig, ax = plt.subplots(figsize=(WIDTH_IN, height), layout="constrained",
                           dpi=min(dpi, MAX_DPI))
    ax.plot(*outline.T, "--", color="0.55", lw=0.8, label="t = 0")
    ax.set(xlim=(0, xmax), ylim=(0, zmax), aspect="equal", xlabel=f"{x} (m)", ylabel="z (m)")
    scale = plt.cm.ScalarMappable(norm=plt.Normalize(0, vmax), cmap="viridis")
    fig.colorbar(scale, ax=ax, label="speed |u| (m/s)", fraction=0.03, pad=0.01, shrink=0.9)
    ax.plot([], [], color="tab:red", lw=1.2, label="static/flowing interface (1 mm/s)")
    ax.legend(loc="upper right", fontsize=7, frameon=False)
    title = ax.set_title(" ", loc="left", fontsize=10)
    if note:
        ax.set_title(note.strip(" ()"), loc="right", fontsize=8, color="0.35")
    fig.canvas.draw()
    title.set_animated(True)
    background = fig.canvas.copy_from_bbox(fig.bbox)
    images = []
    for f in frames:
        fig.canvas.restore_region(background)
        speed = vertex_speed(f)
        mesh = mtri.Triangulation(f["xy"][:, 0], f["xy"][:, 1], f["tri"])
        artists: list[Any] = [ax.tripcolor(mesh, speed, shading="gouraud", cmap="viridis",
                                           vmin=0, vmax=vmax, animated=True)]
        if speed.max() > FLOWING_SPEED > speed.min():
            artists.append(ax.tricontour(mesh, speed, levels=[FLOWING_SPEED],
                                         colors="tab:red", linewidths=1.2))
            artists[-1].set_animated(True)
        title.set_text(f"t = {float(f['t']):.2f} s")
        for artist in (*artists, title):
            ax.draw_artist(artist)
        rgba = np.asarray(fig.canvas.buffer_rgba())
        images.append(Image.fromarray(rgba[..., :3].copy()).quantize(
            colors=COLOURS, dither=Image.Dither.NONE))
        for artist in artists:
            artist.remove()
    plt.close(fig)
    with atomic_file(path) as tmp:
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:],
                       duration=FRAME_MS, loop=0)
