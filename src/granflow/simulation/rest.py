"""Stopping at rest: the run ends once the mass has stayed at rest long enough to be sure.

The rule: the mass is at rest when the cells flowing faster than the static/flowing
threshold (1 mm/s, paper section 5.1.2) hold at most ``fraction`` of the area; the run
ends when it has been at rest without interruption for ``duration`` seconds since the
motion began. A fraction rather than "every cell" because the regularised law lets a thin
tip, where the pressure and with it the yield stress vanish, creep viscously just above the
threshold for ever (a 10 cm square column keeps 0.08 % of its cells at 1.09 mm/s to
t = 1.5 s): that tip moves by about a millimetre per second, below what the mesh or an
experiment resolves, while the deposit is otherwise still.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import ClassVar, Protocol

from granflow.state.spec import FLAG, TIME, Share, or_none

FLOWING_SPEED = 1e-3  # m/s: a cell flows when |u| exceeds it (paper section 5.1.2)


class Clock(Protocol):
    """What the criterion reads of the loop (``Simulation``): its time."""

    t: float


@dataclass
class RestCriterion:
    """Stop criterion of the time loop; ``flowing_fraction`` reads the accepted state."""

    flowing_fraction: Callable[[], float]
    fraction: float
    duration: float
    moved: bool = False
    rest_since: float | None = field(default=None)
    share: ClassVar[Share] = {"moved": FLAG, "rest_since": or_none(TIME)}   # of a checkpoint

    def save_state(self) -> dict[str, object]:
        return {"moved": self.moved, "rest_since": self.rest_since}

    def restore_state(self, state: dict[str, object]) -> None:
        self.moved = bool(state["moved"])
        rest_since = state["rest_since"]
        self.rest_since = None if rest_since is None else float(rest_since)  # type: ignore[arg-type]

    def __call__(self, sim: Clock) -> str | None:
        if self.flowing_fraction() > self.fraction:
            self.moved, self.rest_since = True, None
            return None
        if not self.moved:
            return None
        if self.rest_since is None:
            self.rest_since = sim.t
        if sim.t - self.rest_since >= self.duration * (1 - 1e-9):
            return (f"the mass came to rest at t = {self.rest_since:.4g} s (cells faster than "
                    f"1 mm/s held at most {self.fraction:g} of the area for "
                    f"{self.duration:g} s)")
        return None
