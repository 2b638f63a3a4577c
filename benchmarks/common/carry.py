"""Carrying a study's finished rows past the end time they were run to: a row that reached
its end still moving is continued from its checkpoint (``granflow.resume`` with a later
``time.t_end``); a row records the end it ran to and keeps its figures at the earlier ends,
so that an invocation with an earlier end keeps it as it is (never runs it again, never
shortens it). A run that outlives the machine it started on travels in the repository: an
interrupted run's folder is packed (``pack``) and a fresh clone's invocation unpacks it
(``unpack``) and continues it from its checkpoint."""

from __future__ import annotations

import tarfile
from pathlib import Path

import granflow
from common.runs import FINISHED
from granflow.io.run_dir import LOCK_FILE, RunDir

STUDY_END = 3.0     # s: the end of rows recorded before they kept their end (``t_end``)
BED_LENGTH = "geometry.bed_length="
OUTPUTS = ("frames", "plots", "profiles")   # a run folder's outputs, not packed


def ended(row: dict) -> float:
    """The end time a row was run to."""
    return float(row.get("t_end", STUDY_END))


def settled(row: dict, t_end: float) -> bool:
    """A finished row needing no more time: at rest, or run to ``t_end`` or later."""
    return row.get("status") == "stopped" or (
        row.get("status") in FINISHED and ended(row) >= t_end - 1e-9)


def same_run(recorded: list[str], found: list[str]) -> bool:
    """The recorded overrides are ``found``'s but for a bed at least as long: the layer
    reaching further beyond a front that never gets there is the same run (a row started
    before its rigid twin had finished set its bed by the slope, ``overrides``)."""
    def parts(given: list[str]) -> tuple[list[str], float]:
        bed = [o for o in given if o.startswith(BED_LENGTH)]
        return ([o for o in given if o not in bed],
                float(bed[0].removeprefix(BED_LENGTH)) if bed else 0.0)
    (rest, length), (rest_found, length_found) = parts(recorded), parts(found)
    return rest == rest_found and length >= length_found - 1e-12


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


def pack(folder: Path, archive: Path) -> None:
    """What a resume needs of the run's folder (its config, checkpoint, records and
    manifest; not its lock, nor the outputs written so far: the frames, profiles, plots and
    VTK fields stay with the machine that wrote them) into the compressed ``archive``,
    written beside and renamed into place."""
    archive.parent.mkdir(parents=True, exist_ok=True)
    part = archive.with_name(archive.name + ".part")
    with tarfile.open(part, "w:gz") as tar:
        for path in sorted(folder.rglob("*")):
            relative = path.relative_to(folder)
            if path.is_file() and resume_needs(relative):
                tar.add(path, arcname=str(relative))
    part.replace(archive)


def resume_needs(relative: Path) -> bool:
    """Whether a file of a run folder (its path inside it) is packed."""
    return (relative.name != LOCK_FILE and relative.suffix != ".vtu"
            and relative.parts[0] not in OUTPUTS)


def unpack(archive: Path, folder: Path) -> bool:
    """Restore ``folder`` from ``archive`` when the folder holds no checkpoint (a fresh
    clone); tarfile's ``data`` filter refuses links, devices and paths leaving the folder.
    Whether it restored anything."""
    if not archive.is_file() or (folder / "checkpoint" / "state.npz").is_file():
        return False
    folder.mkdir(parents=True, exist_ok=True)
    with tarfile.open(archive, "r:gz") as tar:
        tar.extractall(folder, filter="data")
    return True
