"""The last lines of a run, read from its summary.json: what a user sees when a run ends
(``granflow run``, ``granflow resume``, ``granflow.run(progress=True)``) and what
``Run.report()`` gives for any run directory.

    stopped: at rest from t = 0.888 s (run to t = 0.938 s, 956 steps)
      runout              0.6646 m
      height at the wall  0.2143 m
      volume error        2.2e-16 after corrections of 0.74 % in all (net -0.46 %)
      wall time           48.8 s
      figures             runs/trapezoid-rigid-20261204-101500/plots

Paths are printed relative to the working folder when they lie under it (``display_path``),
on every line alike.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

LABEL_WIDTH = 18


def display_path(path: Path) -> str:
    """``path`` relative to the working folder when it lies under it, else as given."""
    try:
        return str(Path(path).resolve().relative_to(Path.cwd().resolve()))
    except (ValueError, OSError):
        return str(path)


def headline(summary: Mapping[str, Any]) -> str:
    """Status and when the run ended: the stop time of a mass at rest, "still moving at
    t_end" for one that was not, where a failed or interrupted run stood."""
    status = str(summary.get("status", "failed"))
    t = _number(summary.get("t_final"))
    stop = _number(summary.get("stop_time_s"))
    steps = summary.get("steps")
    counts = f", {steps} steps" if isinstance(steps, int) else ""
    if status == "stopped" and stop is not None:
        ran = f"run to t = {t:.3f} s" if t is not None else "run"
        return f"stopped: at rest from t = {stop:.3f} s ({ran}{counts})"
    if status == "completed":
        end = f"t_end = {t:g} s" if t is not None else "t_end"
        if stop is not None:
            return f"completed: at rest from t = {stop:.3f} s, run to {end}{counts}"
        return f"completed: still moving at {end}{counts}"
    if status == "running":
        return "running: not finished (or killed; `granflow resume` continues it)"
    where = f" at t = {t:.4g} s" if t is not None else ""
    return f"{status}{where}{counts}: {summary.get('message', '')}".rstrip(": ")


def final_lines(summary: Mapping[str, Any], root: Path) -> list[str]:
    """The headline, then the results a run has (runout, final height at the wall or on
    the axis, volume error, wall time) and where its figures are."""
    rows: list[tuple[str, str]] = []
    runout = _number(summary.get("runout_m"))
    if runout is not None:
        rows.append(("runout", f"{runout:.4f} m"))
    axis = _number(summary.get("axis_height_m"))
    wall = _number(summary.get("wall_height_m"))
    if axis is not None:
        rows.append(("height on the axis", f"{axis:.4f} m"))
    elif wall is not None:
        rows.append(("height at the wall", f"{wall:.4f} m"))
    error = _number(summary.get("velocity_relative_error_l2"))
    if error is not None:
        against = ("the steady profile" if summary.get("reference") == "steady"
                   else "the 1D solution")
        rows.append(("velocity error", f"{error:.3g} (relative L2, against {against})"))
    volume = _number(summary.get("volume_relative_error"))
    if volume is not None:
        rows.append(("volume error", f"{volume:.2g}{_correction(summary)}"))
    wall_time = _number(summary.get("wall_time_s"))
    if wall_time is not None:
        rows.append(("wall time", f"{wall_time:.1f} s"))
    plots = Path(root) / "plots"
    if (plots / "error.txt").is_file():
        rows.append(("figures", f"not drawn: see {display_path(plots / 'error.txt')}"))
    elif plots.is_dir():
        rows.append(("figures", display_path(plots)))
    rows.append(("run directory", display_path(Path(root))))
    return [headline(summary), *(f"  {name:<{LABEL_WIDTH}}  {value}" for name, value in rows)]


def _correction(summary: Mapping[str, Any]) -> str:
    """What restoring the area after each move cost (``numerics.volume_correction``): the
    volume error is then right by construction, and this is how far the moves drifted."""
    total = _number(summary.get("area_correction_total"))
    if not total:
        return ""
    net = _number(summary.get("area_correction_net")) or 0.0
    return f" after corrections of {100 * total:.2g} % in all (net {100 * net:+.2g} %)"


def _number(value: Any) -> float | None:
    return float(value) if isinstance(value, int | float) and not isinstance(value, bool) \
        and value == value else None
