"""``granflow plot RUN_DIR``: every figure (and the animation) again, from the files alone.

Reads config.toml, profiles/, diagnostics.csv and frames/ only, so it works on a run that
was killed or is still running (what is written so far), and after a figure was deleted.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from granflow.config import load_config
from granflow.io.run_dir import RunDir, RunDirError


def plot_run(root: Path) -> list[Path]:
    """Regenerate the figures of the run in ``root``; return the files written."""
    if not RunDir.is_run_dir(root):
        raise RunDirError(f"'{root}' is not a granflow run directory (no config.toml)")
    config = load_config(str(Path(root) / "config.toml"))
    run_dir = RunDir(Path(root))
    if config.geometry.kind == "periodic-layer":
        _plot_plug_flow(run_dir)
    else:
        from granflow.io.collapse_plots import plot_collapse

        plot_collapse(run_dir, config)
    return sorted((Path(root) / "plots").glob("*.*"))


def _plot_plug_flow(run_dir: RunDir) -> None:
    """The velocity profile against the 1D reference at the last output time on disk."""
    from granflow.io.plots import plot_plug_profile

    profiles = sorted(run_dir.root.glob("profiles/velocity_t*.csv"),
                      key=lambda p: float(re.findall(r"t([0-9.]+)\.csv$", p.name)[0]))
    if not profiles:
        raise RunDirError(f"'{run_dir.root}' holds no velocity profile yet (profiles/ is "
                          "written at time.output_times)")
    last = profiles[-1]
    data = np.genfromtxt(last, delimiter=",", names=True)
    t = float(re.findall(r"t([0-9.]+)\.csv$", last.name)[0])
    plot_plug_profile(run_dir.path("plots/velocity_profile.png"), data["z"], data["u_x"],
                      data["u_reference"], t)
