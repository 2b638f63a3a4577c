"""The rigid bed's keys as the configuration sees them (engine-free): which of them a run
on a column's or a slab's bed does not read (``scenarios/bed.py`` builds the bed)."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config


def bed_inert_keys(c: Config) -> dict[str, str]:
    """The Coulomb bed's friction on another bed; the fluidity's condition on a bed that
    does not slide (there g = 0)."""
    bed = c.boundary.bed
    out: dict[str, str] = {}
    if bed != "coulomb":
        out["boundary.bed_friction_deg"] = (f"boundary.bed = {bed!r}: it is the Coulomb "
                                            "bed's friction")
    if bed == "no-slip":
        out["boundary.bed_fluidity"] = ("boundary.bed = 'no-slip': the nonlocal fluidity is "
                                        "0 on a bed that does not slide")
    return out
