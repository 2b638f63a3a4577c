"""The entrainment figure of a collapse over an erodible layer, from the run's files: the
last deposit with the layer material coloured by where it started, the erosion depth along
the bed, and the fronts and eroded areas against time (``scenarios/column_layer.py`` says
what each measure is)."""

from __future__ import annotations

from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from granflow.geometry.section import Section  # noqa: E402
from granflow.io import profiles  # noqa: E402
from granflow.io.diagnostics import read_diagnostics  # noqa: E402
from granflow.io.plots import FigureFormat  # noqa: E402
from granflow.io.run_dir import RunDir  # noqa: E402


def plot_erosion(run_dir: RunDir, config: Any, section: Section,
                 fmt: FigureFormat | None = None) -> None:
    """plots/erosion.png (or the configured format), if the run has written its layer's
    profiles; ``section``: plane, or the r-z section of a cylinder."""
    markers = profiles.final_profile(run_dir.root, "layer_markers")
    found = profiles.list_profiles(run_dir.root, "layer_markers")
    if markers is None and found:
        markers = found[-1].read()
    if markers is None:
        return
    x = section.coordinate
    he = config.geometry.erodible_thickness
    # each panel's legend in a column of its own, beside it: never over the data
    fig, axes = plt.subplots(3, 2, figsize=(10, 8.5), height_ratios=[1.3, 1, 1],
                             width_ratios=[4, 1.1], layout="constrained")
    for key in axes[:, 1]:
        key.axis("off")
    _deposit(axes[0, 0], run_dir, markers, x, he)
    _depths(axes[1, 0], run_dir, x, he)
    twin = _history(axes[2, 0], run_dir, section)
    for (panel, key), extra in zip(axes, (None, None, twin), strict=True):
        handles, labels = panel.get_legend_handles_labels()
        if extra is not None:
            more = extra.get_legend_handles_labels()
            handles, labels = handles + more[0], labels + more[1]
        if handles:
            key.legend(handles, labels, loc="center left", fontsize=7, frameon=False)
    (fmt or FigureFormat.of(config)).save(fig, run_dir, "erosion")


def _deposit(ax: plt.Axes, run_dir: RunDir, markers: dict[str, np.ndarray], x: str,
             he: float) -> None:
    surface = profiles.final_profile(run_dir.root, "free_surface")
    line = profiles.final_profile(run_dir.root, "layer_line")
    if surface is not None:
        ax.fill_between(surface["x"], 0, surface["z"], color="0.85", lw=0)
        ax.plot(surface["x"], surface["z"], color="k", lw=0.8, label="free surface")
    if line is not None:
        ax.plot(line["x"], line["z"], color="tab:red", lw=0.8, label="top of layer material")
    points = ax.scatter(markers["x"], markers["z"], c=markers["x0"], s=2, cmap="viridis",
                        label="layer material")
    plt.colorbar(points, ax=ax, label=f"initial {x} (m)", pad=0.01)
    front = markers["x"][markers["travel"] > 0].max() if (markers["travel"] > 0).any() else 0
    ax.set(xlim=(0, max(front, markers["x"].max()) * 1.02), ylim=(0, 6 * he),
           xlabel=f"{x} (m)", ylabel="z (m)",
           title=f"Last state near the bed, layer material coloured by its initial {x}")


def _depths(ax: plt.Axes, run_dir: RunDir, x: str, he: float) -> None:
    found_all = profiles.list_profiles(run_dir.root, "erosion_depth")
    last = next((f.read() for f in found_all if f.final), None)
    for found in found_all:
        data = found.read()
        label = "last state" if found.final else f"t = {found.t:.2f} s"
        if not found.final and last is not None and len(last["depth"]) == len(
                data["depth"]) and np.allclose(last["depth"], data["depth"]):
            label += " (= last state)"      # the same curve: under the last state's
        # the last state dashed: an output time after the layer stopped shows through it
        ax.step(data["x0"], data["depth"], where="mid", label=label,
                color="k" if found.final else None, lw=1.2 if found.final else 0.8,
                ls=(0, (4, 2)) if found.final else "-")
    ax.axhline(he, color="0.6", ls="--", lw=0.8, label="layer thickness")
    ax.set(xlabel=f"initial {x} (m)", ylabel="depth (m)",
           title="Erosion depth: layer material moved more than one grain diameter")
    ax.invert_yaxis()


def _history(ax: plt.Axes, run_dir: RunDir, section: Section) -> plt.Axes | None:
    """The fronts, and on a second axis the eroded areas (returned)."""
    diag = read_diagnostics(run_dir.root)
    if not len(diag) or "column_front_x" not in diag:
        return None
    ax.plot(diag["t"], diag["front_x"], label="flow front (1 mm above the layer)")
    ax.plot(diag["t"], diag["column_front_x"], label="column material front")
    ax.plot(diag["t"], diag["erosion_front_x"], label="erosion front (layer in motion)")
    ax.set(xlabel="t (s)", ylabel=f"{section.coordinate} (m)", title="Fronts and eroded areas")
    twin = ax.twinx()
    twin.plot(diag["t"], diag["layer_displaced_area"], "k--", lw=0.8, label="displaced")
    twin.plot(diag["t"], diag["layer_mobilised_area"], "k:", lw=0.8, label="in motion")
    twin.set_ylabel(f"layer {section.amount} ({section.amount_label})")
    return twin
