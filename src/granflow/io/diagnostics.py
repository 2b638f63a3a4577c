"""``diagnostics.csv``: one row per accepted step, its one writer and its one reader.

Columns: t (s), dt (s), iterations, front_x (m), wall_height (m), volume (m^2 per metre of
width), kinetic_energy (J/m), max_speed (m/s), flowing_fraction, linear_solves,
local_error, tension_on, tension_x (m), area_correction, remesh_area_change (relative);
then the columns the problem's parts declare (``simulation/outputs.py``), in the order they
were added to the loop: over an erodible layer the entrainment columns (areas in m^2 per
metre, positions and depth in m, the area drift relative; ``scenarios/column_layer.py``),
with a hysteretic friction ``mobilised_fraction``, the mean mobilisation of the mass
(``scenarios/mobilisation_tracking.py``).
In an axisymmetric run front_x is the radius r (m), volume is the volume of revolution (m^3)
and kinetic_energy the whole body's (J). The file is append-only and flushed after each
row; a resumed run first cuts it back to the rows its checkpoint had seen, then appends.
"""

from __future__ import annotations

import io
import math
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

from granflow.io.run_dir import CsvLog, RunDir, atomic_write_bytes
from granflow.io.untrusted import RunDirError, is_regular, read_text
from granflow.state.spec import COUNT, Share, may_lack

if TYPE_CHECKING:
    import pandas as pd

FILE = "diagnostics.csv"
COLUMNS = ["t", "dt", "iterations", "front_x", "wall_height", "volume",
           "kinetic_energy", "max_speed", "flowing_fraction", "linear_solves",
           "local_error", "tension_on", "tension_x", "area_correction",
           "remesh_area_change"]


class DiagnosticsLog:
    """The open diagnostics.csv of a run, ``COLUMNS`` then ``columns`` (those the
    problem's parts declare); ``rows`` is what a checkpoint remembers."""

    name = "diagnostics"
    share: ClassVar[Share] = {"diagnostic_rows": may_lack(COUNT)}    # of a checkpoint

    def __init__(self, run_dir: RunDir, resume: Mapping[str, Any] | None = None,
                 columns: Sequence[str] = ()) -> None:
        self.rows = int(resume.get("diagnostic_rows", 0)) if resume else 0
        path = run_dir.path(FILE)
        if resume is not None:
            _truncate_rows(path, self.rows)
        self.columns = COLUMNS + [c for c in columns if c not in COLUMNS]
        self._log: CsvLog = run_dir.csv_log(FILE, self.columns, resume=resume is not None)

    def write(self, row: Mapping[str, float]) -> None:
        """One row; columns the row lacks are NaN (a plug flow has no front)."""
        self._log.write([row.get(c, math.nan) for c in self.columns])
        self.rows += 1

    def save_state(self) -> dict[str, Any]:
        return {"diagnostic_rows": self.rows}

    def close(self) -> None:
        self._log.close()


def read_diagnostics(root: Path) -> pd.DataFrame:
    """diagnostics.csv of the run in ``root`` as a DataFrame (empty if not written yet)."""
    import pandas as pd

    path = Path(root, FILE)
    text = read_text(path) if os.path.lexists(path) else ""
    if not text:
        return pd.DataFrame(columns=COLUMNS)
    try:
        table = pd.read_csv(io.StringIO(text), low_memory=False)   # whole columns typed
    except (ValueError, pd.errors.ParserError) as err:
        raise RunDirError(f"'{path}' is not a CSV table: {str(err).strip()[:200]}") from None
    odd = [c for c in table.columns if table[c].dtype.kind not in "biuf"]
    if "t" not in table.columns or odd:
        raise RunDirError(f"'{path}' is not granflow's diagnostics: "
                          + (f"column {odd[0]!r} is not numbers" if odd else "no column t"))
    return table


def _truncate_rows(path: Path, rows: int) -> None:
    """Keep the header and the first ``rows`` rows of the log (those the checkpoint has
    seen): rows written after it by the killed run are replayed by the resumed one."""
    if not is_regular(path):
        return
    lines = read_text(path).splitlines(keepends=True)
    atomic_write_bytes(path, "".join(lines[:rows + 1]).encode("utf-8"))
