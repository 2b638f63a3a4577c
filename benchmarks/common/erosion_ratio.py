"""The erosion study's measure: a layer row's runout over its rigid twin's, with the bounds
a front still moving at the end gives, and the twin's front read as a layer row's is.

A layer row's front is the furthest surface point 1 mm above the undisturbed layer; a
rigid row's ``runout_m`` is the furthest point of the mass, the thin tongue a sliding front
leaves included. ``runout_1mm_m`` reads the rigid row's front 1 mm above the bed: the same
measure as the layer row's (``docs/outputs.md``)."""

from __future__ import annotations

from common.carry import ended
from common.erosion_variants import RIGID_TWIN

CELLS = 2   # across the layer, unless --cells says otherwise


def key(variant: str, shape: str, he: float, slope: float, cells: int = CELLS) -> str:
    """The run's name (and folder): a layer of other than two cells says how many."""
    tail = f"-{cells}cells" if he > 0 and cells != CELLS else ""
    return f"{variant}/{shape}-{1e3 * he:g}mm-{slope:g}{tail}"


def rigid_key(variant: str, shape: str, slope: float) -> str:
    """The rigid-bed run a variant's ratio is taken against."""
    return key(RIGID_TWIN.get(variant, variant), shape, 0.0, slope)


def runout(row: dict) -> float | None:
    """The runout once the front is at rest (None while it still moves, or if it failed)."""
    settled = row.get("status") == "stopped" or (
        row.get("status") == "completed" and row.get("front_stop_time_s") is not None)
    return row.get("runout_m") if settled else None


def front(row: dict) -> float | None:
    """The front at t_end of a run that reached it still moving (None otherwise)."""
    return row.get("runout_m") if row.get("status") == "completed" else None


def at_1mm(row: dict) -> dict:
    """A rigid row with its front read 1 mm above the bed, as a layer row's is; its fronts
    on the clock (the furthest point) left out. Empty where the record has no such front."""
    if row.get("runout_1mm_m") is None:
        return {}
    return {k: v for k, v in row.items() if k != "front_history"} | {
        "runout_m": row["runout_1mm_m"]}


def ratio(results: dict[str, dict], row: dict,
          thick: bool = False) -> tuple[float | None, str]:
    """The erodible row's runout over its rigid twin's (``thick``: the twin's front 1 mm
    above the bed), and what it is: "" both settled; "≤" an upper bound, the rigid front
    still moving at t_end (it only goes further); "≥" a lower bound, the erodible front
    still moving; "≈" both moving, their fronts at t_end (at the earlier end of the two,
    from the other's ``front_history``, where they ran to different ends). None for a rigid
    row or one that failed."""
    rigid = results.get(rigid_key(row["variant"], row["shape"], row["slope"]), {})
    rigid = at_1mm(rigid) if thick else rigid
    x, x0 = runout(row), runout(rigid)
    if row["he"] == 0:
        return None, ""
    if x is not None:
        if x0:
            return x / x0, ""
        return (x / front(rigid), "≤") if front(rigid) else (None, "")
    if front(row) is None:
        return None, ""
    if x0:
        return front(row) / x0, "≥"
    if not front(rigid):
        return None, ""
    end = min(ended(row), ended(rigid))
    mine, theirs = (front(r) if ended(r) == end else r.get("front_history", {}).get(f"{end:g}")
                    for r in (row, rigid))
    return (mine / theirs, "≈") if mine and theirs else (None, "")
