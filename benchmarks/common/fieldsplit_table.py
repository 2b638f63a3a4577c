"""The table of the FGMRes fieldsplit variants that ``three_d_fieldsplit.py --table``
prints and writes (table.json; docs/three_d.md quotes it): outer steps by state and size,
the largest distance to the direct solve, and the stopping test's ranges from the
records' ``history``."""

from __future__ import annotations

import json
from pathlib import Path

TABLE_KINDS = {"selfp, unscaled": "ranks_flexible_rigid",
               "selfp, scaled": "ranks_flexible_rigid_scaled",
               "Cahouet-Chabard, unscaled": "ranks_cahouet-chabard_rigid",
               "Cahouet-Chabard, scaled": "ranks_cahouet-chabard_rigid_scaled",
               "LSC, unscaled": "ranks_lsc-gamg-flexible_rigid",
               "LSC, scaled": "ranks_lsc-gamg-flexible_rigid_scaled"}
TABLE_SIZES = ("0.04", "0.02", "0.014")


def table_cell(folder: Path, kind: str, state: str) -> str:
    """Outer steps at each size ("fails" where a solve did not converge) and the largest
    relative distance of the velocity or the pressure to the direct solve, one process."""
    steps, apart = [], []
    for size in TABLE_SIZES:
        path = folder / f"fieldsplit_{kind}_{state}_h{size}_n1.json"
        if not path.exists():
            continue
        record = json.loads(path.read_text())
        steps.append(str(record["steps"]) if record["converged"] else "fails")
        apart.append(max(record["velocity_pressure_difference"]))
    return " / ".join(steps) + (f" ({max(apart):.0e})" if apart else "")


def table(folder: Path) -> str:
    """The Markdown table of the FGMRes variants (``TABLE_KINDS``) by state."""
    lines = ["| variant | rest | flowing | front |", "|---|---|---|---|"]
    for name, kind in TABLE_KINDS.items():
        lines.append(f"| {name} | " + " | ".join(table_cell(folder, kind, state) for state
                                                  in ("rest", "flowing", "front")) + " |")
    return "\n".join(lines)


def stopping(folder: Path, kind: str, target: float = 1e-6) -> dict:
    """From the ``history`` of a variant's records (every state and size): at the first
    step where the velocity and the pressure are both within ``target`` of the direct
    solve, the range of FGMRes' own relative residual (of the system it solves: scaled
    or not) and of the unscaled system's true relative residual; the largest distance at
    the first step where FGMRes' own relative residual is below 1e-8, and at the end."""
    own, true, apart, at_1e8 = [], [], [], []
    for path in sorted(folder.glob(f"fieldsplit_{kind}_*_n1.json")):
        record = json.loads(path.read_text())
        if not any(path.name == f"fieldsplit_{kind}_{state}_h{size}_n1.json"
                   for state in ("rest", "flowing", "front") for size in TABLE_SIZES):
            continue
        history = record["history"]
        apart.append(max(record["velocity_pressure_difference"]))
        first = next((h for h in history if max(h[3:]) < target), None)
        if first is not None:
            own.append(first[1] / history[0][1])
            true.append(first[2])
        below = next((h for h in history if h[1] / history[0][1] < 1e-8), None)
        if below is not None:
            at_1e8.append(max(below[3:]))
    return {"records": len(apart), "reached": len(own),
            "own_residual": [min(own), max(own)] if own else None,
            "true_residual": [min(true), max(true)] if true else None,
            "largest_distance_at_1e-8": max(at_1e8) if at_1e8 else None,
            "largest_distance": max(apart) if apart else None}
