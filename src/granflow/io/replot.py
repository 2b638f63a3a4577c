"""What ``granflow plot RUN_DIR`` needs beside the figures themselves: the run's
configuration with the figure format asked for, and the figure files it then holds. The
figures are drawn from the run directory's files through their readers (``io/profiles.py``,
``io/diagnostics.py``, ``io/frames.py``), never from a solver's private state, so a figure
always shows what the files hold; which figures a run has is its problem kind's
(``scenarios/registry.py``)."""

from __future__ import annotations

from pathlib import Path

from granflow.config import Config, apply_overrides, load_config


def figure_config(root: Path, figure_format: str | None = None,
                  dpi: int | None = None) -> Config:
    """The configuration of the run in ``root``, in ``figure_format`` (png, pdf, svg) at
    ``dpi`` where given."""
    config = load_config(str(Path(root) / "config.toml"))
    chosen = {k: v for k, v in (("output.figure_format", figure_format), ("output.dpi", dpi))
              if v is not None}
    return apply_overrides(config, chosen) if chosen else config


def figure_files(root: Path, config: Config) -> list[Path]:
    """The figures in RUN_DIR/plots in the configuration's format, and the animation."""
    suffix = config.output.figure_format
    return sorted(p for p in (Path(root) / "plots").glob("*.*")
                  if p.suffix in (f".{suffix}", ".gif"))
