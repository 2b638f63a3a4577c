"""What an erodible run did in time and where its layer went, read from its run directory:
the front's position on a fixed clock (to set beside its rigid twin's), its speed at the end
(a run that creeps at t_end), and the layer's displaced material by where it started and
where it ended (``layer_markers``: every marker stands for the same area in plane strain)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from granflow.io import profiles
from granflow.io.diagnostics import read_diagnostics

CLOCK = (0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 2.5, 3.0)   # s: the fronts compared there
END_WINDOW = 0.1     # s: the front's speed at the end is its mean over this last window


def front_history(root: Path, clock: tuple[float, ...] = CLOCK) -> dict[str, float]:
    """The front (``front_x``, m) at each time of ``clock`` the run reached, by "T"."""
    diag = read_diagnostics(root)
    if not len(diag):
        return {}
    t, x = diag["t"].to_numpy(), diag["front_x"].to_numpy()
    return {f"{c:g}": float(np.interp(c, t, x)) for c in clock if c <= t[-1] + 1e-9}


def front_speed_end(root: Path, window: float = END_WINDOW) -> float | None:
    """The front's mean speed (m/s) over the run's last ``window`` seconds."""
    diag = read_diagnostics(root)
    if len(diag) < 2:
        return None
    t, x = diag["t"].to_numpy(), diag["front_x"].to_numpy()
    start = max(t[0], t[-1] - window)
    if t[-1] <= start:
        return None
    return float((x[-1] - np.interp(start, t, x)) / (t[-1] - start))


def layer_destination(root: Path, grain: float, column_width: float,
                      column_front: float | None) -> dict[str, float]:
    """The displaced layer material (markers that travelled further than ``grain``) at the
    run's end: the share of it that started under the column (x0 below ``column_width``)
    and that ended ahead of the column's material (x beyond ``column_front``), its median
    and largest advance along the bed (m), where it started (x0 range, m) and the furthest
    it ended (m)."""
    markers = profiles.final_profile(root, "layer_markers")
    if not markers:
        return {}
    x, x0 = np.asarray(markers["x"]), np.asarray(markers["x0"])
    travel = np.asarray(markers["travel"])
    moved = travel > grain
    if not moved.any():
        return {}
    advance = x[moved] - x0[moved]
    out = {"displaced_from_under_column_share": float((x0[moved] < column_width).mean()),
           "displaced_advance_median_m": float(np.median(advance)),
           "displaced_advance_max_m": float(advance.max()),
           "displaced_origin_min_m": float(x0[moved].min()),
           "displaced_origin_max_m": float(x0[moved].max()),
           "displaced_end_max_m": float(x[moved].max())}
    if column_front is not None and np.isfinite(column_front):
        out["displaced_ahead_of_column_share"] = float((x[moved] > column_front).mean())
    return out


def at_rest_on(row: dict, clock: tuple[float, ...] = CLOCK) -> dict[str, float]:
    """A row's ``front_history``, and for a run that stopped at rest its runout at the
    times of ``clock`` after its end (its front stays there)."""
    history = dict(row.get("front_history", {}))
    if row.get("status") == "stopped" and row.get("runout_m") is not None:
        for c in clock:
            history.setdefault(f"{c:g}", row["runout_m"])
    return history


def fronts_table(pairs: list[tuple[str, dict, dict]], clock: tuple[float, ...] = CLOCK) -> str:
    """Markdown: per erodible row (name, row, its rigid twin's row), the front over the
    layer minus the rigid twin's (mm) at each time of ``clock`` (``at_rest_on``; a deficit
    is negative), and each front's speed at the end (mm/s)."""
    head = ["row", *(f"{c:g} s" for c in clock), "front speed at the end, layer / rigid (mm/s)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name, row, rigid in pairs:
        mine, theirs = at_rest_on(row, clock), at_rest_on(rigid, clock)
        cells = [f"{1e3 * (mine[k] - theirs[k]):+.0f}" if k in mine and k in theirs else "-"
                 for k in (f"{c:g}" for c in clock)]
        speeds = [r.get("front_speed_end_m_s") for r in (row, rigid)]
        shown = " / ".join("-" if v is None else f"{1e3 * v:.1f}" for v in speeds)
        lines.append("| " + " | ".join([name, *cells, shown]) + " |")
    return "\n".join(lines) + "\n"


def destination_table(rows: list[tuple[str, dict]]) -> str:
    """Markdown: per erodible row, where its displaced layer material went
    (``layer_destination`` and the summary's areas)."""
    head = ["row", "displaced (cm^2)", "as layer length (m)", "largest mobilised (cm^2)",
            "deepest (mm)", "from under the column", "ended ahead of the column's material",
            "advance median / max (cm)", "origin x0 (m)"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]

    def num(v: float | None, fmt: str, scale: float = 1.0) -> str:
        return "-" if v is None else format(scale * v, fmt)

    for name, r in rows:
        he = r.get("he") or float("nan")
        area = r.get("layer_displaced_area_m2")
        lines.append("| " + " | ".join([
            name, num(area, ".1f", 1e4), num(None if area is None else area / he, ".3f"),
            num(r.get("layer_mobilised_area_max_m2"), ".1f", 1e4),
            num(r.get("erosion_depth_max_m"), ".1f", 1e3),
            num(r.get("displaced_from_under_column_share"), ".0%"),
            num(r.get("displaced_ahead_of_column_share"), ".0%"),
            f"{num(r.get('displaced_advance_median_m'), '.1f', 100)} / "
            f"{num(r.get('displaced_advance_max_m'), '.1f', 100)}",
            f"{num(r.get('displaced_origin_min_m'), '.3f')}-"
            f"{num(r.get('displaced_origin_max_m'), '.3f')}"]) + " |")
    return "\n".join(lines) + "\n"
