"""The figures of a run, drawn from its files through their readers (``io/profiles.py``,
``io/diagnostics.py``, ``io/frames.py``): at the end of a run and by ``granflow plot
RUN_DIR``, which works on a run that was killed or is still running (what is written so
far) and after a figure was deleted. Nothing is drawn from a solver's private state, so a
figure always shows what the files hold."""

from __future__ import annotations

from pathlib import Path

from granflow.config import Config, apply_overrides, load_config
from granflow.io import profiles
from granflow.io.run_dir import RunDir, RunDirError


def plot_run(root: Path, figure_format: str | None = None, dpi: int | None = None) -> list[Path]:
    """Regenerate the figures of the run in ``root``, in its configuration's format or in
    ``figure_format`` (png, pdf, svg) at ``dpi``; return the files written."""
    if not RunDir.is_run_dir(root):
        raise RunDirError(f"'{root}' is not a granflow run directory (no config.toml)")
    config = load_config(str(Path(root) / "config.toml"))
    chosen = {k: v for k, v in (("output.figure_format", figure_format), ("output.dpi", dpi))
              if v is not None}
    if chosen:
        config = apply_overrides(config, chosen)
    suffix = config.output.figure_format
    draw_figures(RunDir(Path(root)), config)
    return sorted(p for p in (Path(root) / "plots").glob("*.*")
                  if p.suffix in (f".{suffix}", ".gif"))


def draw_figures(run_dir: RunDir, config: Config) -> None:
    """Every figure of the run in ``run_dir`` (a collapse or a plug flow) into plots/, in
    ``output.figure_format`` at ``output.dpi``."""
    if config.geometry.kind == "periodic-layer":
        _plot_plug_flow(run_dir, config)
    else:
        from granflow.io.collapse_plots import plot_collapse

        plot_collapse(run_dir, config)


def _plot_plug_flow(run_dir: RunDir, config: Config) -> None:
    """The velocity profile against the 1D reference: of the last accepted state, or of the
    last output time on disk for a run still going."""
    from granflow.io.plots import FigureFormat, plot_plug_profile

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
