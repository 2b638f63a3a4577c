"""Carrying a study's finished rows past the end time they were run to: a row that reached
its end still moving is continued from its checkpoint (``granflow.resume`` with a later
``time.t_end``); a row records the end it ran to and keeps its figures at the earlier ends,
so that an invocation with an earlier end keeps it as it is (never runs it again, never
shortens it)."""

from __future__ import annotations

from pathlib import Path

import granflow
from common.runs import FINISHED
from granflow.io.run_dir import RunDir

STUDY_END = 3.0     # s: the end of rows recorded before they kept their end (``t_end``)


def ended(row: dict) -> float:
    """The end time a row was run to."""
    return float(row.get("t_end", STUDY_END))


def settled(row: dict, t_end: float) -> bool:
    """A finished row needing no more time: at rest, or run to ``t_end`` or later."""
    return row.get("status") == "stopped" or (
        row.get("status") in FINISHED and ended(row) >= t_end - 1e-9)


def carried(summary: dict, out: Path, t_end: float) -> dict:
    """The summary of the run in ``out``; one that reached an earlier end still moving is
    first continued from its checkpoint to ``t_end``."""
    if summary.get("status") == "completed" and summary["t_final"] < t_end - 1e-9:
        granflow.resume(out, {"time.t_end": t_end})
        return RunDir.summary(out)
    return summary


def with_earlier(row: dict, done: dict | None) -> dict:
    """``row`` keeping ``done``'s figures (the same run's earlier record) at the earlier ends
    it was recorded at, by end time (``earlier``): a row carried past 3 s keeps its 3 s."""
    if not done:
        return row
    earlier = dict(done.get("earlier", {}))
    if done.get("status") == "completed" and ended(done) < ended(row):
        earlier[f"{ended(done):g}"] = {k: v for k, v in done.items()
                                       if k not in ("overrides", "earlier")}
    return row | {"earlier": earlier} if earlier else row
