"""Profiles: ``profiles/KIND_LABEL.csv``, their one writer and their one reader.

LABEL is ``tT.TTT`` for an output time T (s) or ``final`` for the last accepted state. Every
row carries its time in a last column ``t`` (s), and ``profiles/units.json`` gives each
column's unit, so a file is readable on its own. Kinds: ``free_surface`` and ``interface``
(x, z), ``velocity_sections`` (section_x, z, u_x, u_z) for a collapse; over an erodible
layer also ``layer_line`` (x, z: the tracked top of the layer material), ``layer_markers``
(x, z now; x0, z0 at t = 0; travel, the largest distance from the origin so far; speed) and
``erosion_depth`` (x0, depth); ``velocity`` (z, u_x, u_z, u_reference) for the plug flow.
x runs along the bed, z normal to it.
"""

from __future__ import annotations

import csv
import io
import os
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from granflow.geometry.polylines import surface_distance
from granflow.io.run_dir import RunDir
from granflow.io.untrusted import RunDirError, read_text

FOLDER = "profiles"
FINAL = "final"
UNITS = {"t": "s", "x": "m", "z": "m", "section_x": "m", "u_x": "m/s", "u_z": "m/s",
         "u_reference": "m/s", "x0": "m", "z0": "m", "travel": "m", "speed": "m/s",
         "depth": "m"}
_NAME = re.compile(r"(?P<kind>[a-z_]+?)_(?P<label>t\d+(?:\.\d+)?|final)\.csv")

Profile = dict[str, np.ndarray]   # column name -> values


def label_of(t: float) -> str:
    """The file label of output time ``t``: ``t0.300``."""
    return f"t{t:.3f}"


def write_profile(run_dir: RunDir, kind: str, t: float, columns: Sequence[str],
                  rows: np.ndarray | Sequence[Sequence[float]], final: bool = False) -> None:
    """``profiles/KIND_tT.TTT.csv`` (or ``KIND_final.csv``) with a last column t = ``t``."""
    data = np.asarray(rows, dtype=float).reshape(-1, len(columns))
    table = np.column_stack([data, np.full(len(data), t)])
    label = FINAL if final else label_of(t)
    run_dir.write_csv(f"{FOLDER}/{kind}_{label}.csv", [*columns, "t"], table.tolist())
    if not run_dir.path(f"{FOLDER}/units.json").exists():
        run_dir.write_json(f"{FOLDER}/units.json", UNITS)


@dataclass(frozen=True)
class ProfileFile:
    """One profile file: its kind, label and time (None for ``final`` in a run written
    before profiles carried their time: summary.json's ``final_profiles_t`` has it)."""

    kind: str
    label: str
    t: float | None
    path: Path

    @property
    def final(self) -> bool:
        return self.label == FINAL

    def read(self) -> Profile:
        return read_profile(self.path)


def list_profiles(root: Path, kind: str) -> list[ProfileFile]:
    """The profiles of ``kind`` in the run directory ``root``: output times in time order,
    then the final state."""
    found = []
    for path in Path(root, FOLDER).glob(f"{kind}_*.csv"):
        match = _NAME.fullmatch(path.name)
        if match is None or match["kind"] != kind:
            continue
        label = match["label"]
        t = _final_time(path) if label == FINAL else float(label[1:])
        found.append(ProfileFile(kind, label, t, path))
    return sorted(found, key=lambda p: (p.final, p.t if p.t is not None else 0.0))


def profile_at(root: Path, kind: str, t: float) -> Profile | None:
    """The profile of ``kind`` written at output time ``t`` (None if there is none)."""
    path = Path(root, FOLDER, f"{kind}_{label_of(t)}.csv")
    return read_profile(path) if os.path.lexists(path) else None


def final_profile(root: Path, kind: str) -> Profile | None:
    """The profile of ``kind`` of the last accepted state (None if there is none)."""
    path = Path(root, FOLDER, f"{kind}_{FINAL}.csv")
    return read_profile(path) if os.path.lexists(path) else None


def curves(root: Path, kind: str,
           times: Sequence[float] | None = None) -> dict[float, np.ndarray]:
    """(x, z) arrays of the ``kind`` profiles at the output times ``times`` (default: all
    that were written), rows with an undefined value dropped; curves with fewer than two
    points are left out (an interface where nothing flows)."""
    if times is None:
        times = [p.t for p in list_profiles(root, kind) if not p.final and p.t is not None]
    out = {}
    for t in times:
        data = profile_at(root, kind, t)
        if not data:
            continue
        xz = np.column_stack([data["x"], data["z"]])
        xz = xz[np.isfinite(xz).all(axis=1)]
        if len(xz) >= 2:
            out[t] = xz
    return out


def surface_distances(first: Path, second: Path, kind: str = "free_surface",
                      times: Sequence[float] | None = None,
                      common_extent: bool = False) -> dict[float, tuple[float, float]]:
    """(mean, max) distance in m between the ``kind`` curves of two runs at each output
    time both wrote (``geometry/polylines.py``). With ``common_extent`` both curves are cut
    where the shorter one ends in X (an erodible layer meshed only ahead of the flow ends
    its free surface at the meshed end; the whole layer's goes on, flat)."""
    a, b = curves(first, kind, times), curves(second, kind, times)
    out = {}
    for t in (t for t in a if t in b):
        pair = (a[t], b[t])
        if common_extent:
            end = min(a[t][:, 0].max(), b[t][:, 0].max())
            pair = (a[t][a[t][:, 0] <= end], b[t][b[t][:, 0] <= end])
        out[t] = surface_distance(*pair)
    return out


def read_profile(path: Path) -> Profile:
    """Columns by name (empty cells and "nan" as NaN); {} for a file with no rows. A file
    that is not such a table (not UTF-8, a cell that is not a number, a row of another
    length) is a ``RunDirError``."""
    rows = _rows(path)
    if not rows:
        return {}
    try:
        return {k: np.array([float(r[k]) if r[k] not in ("", "nan") else np.nan
                             for r in rows]) for k in rows[0] if isinstance(k, str)}
    except (TypeError, ValueError) as err:
        raise RunDirError(f"'{path}' is not a table of numbers: {err}") from None


def _rows(path: Path) -> list[dict[str, str]]:
    try:
        rows = list(csv.DictReader(io.StringIO(read_text(path), newline="")))
    except csv.Error as err:
        raise RunDirError(f"'{path}' is not a CSV table: {err}") from None
    if any(None in row or None in row.values() for row in rows):
        raise RunDirError(f"'{path}': a row has another number of cells than the header")
    return rows


def _final_time(path: Path) -> float | None:
    """The time column's value in a final profile, None if it has none (older runs)."""
    rows = _rows(path)
    if not rows or not rows[0].get("t"):
        return None
    try:
        return float(rows[0]["t"])
    except ValueError:
        raise RunDirError(f"'{path}': its time {rows[0]['t'][:40]!r} is not a number") from None
