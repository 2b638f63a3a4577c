"""Time-step policies: the paper's ramp (section 3.1) and a fixed step."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from granflow.config import Config

RECOVERY_GROWTH = 2.0  # regrowth of dt after a rejected step, once the ramp is over


@dataclass
class RampedStep:
    """dt_{n+1} = growth * dt_n from dt_init up to dt_max; tol ramps likewise (3.1).

    A rejected step halves dt; after the ramp, dt then doubles back to dt_max. Steps are clipped so
    that ``stops`` (output times, t_end) are hit exactly.
    """

    t_end: float
    dt_init: float
    dt_max: float
    growth: float
    tol: float
    tol_init: float
    stops: list[float] = field(default_factory=list)
    dt: float = field(init=False)
    ramp_done: bool = field(init=False, default=False)
    current_tol: float = field(init=False)

    def __post_init__(self) -> None:
        self.dt = min(self.dt_init, self.dt_max)
        self.current_tol = min(self.tol_init, self.tol)
        self.stops = sorted({s for s in self.stops if 0 < s < self.t_end} | {self.t_end})

    def propose(self, t: float) -> tuple[float, float]:
        dt = self.dt
        for stop in self.stops:
            if stop > t + 1e-14:
                if t + dt > stop - 1e-12 * max(1.0, stop):
                    dt = stop - t
                break
        return dt, self.current_tol

    def accepted(self, dt: float) -> None:
        """Grow dt after a full step; a step shortened by a stop or a landing keeps dt."""
        if dt >= self.dt * (1 - 1e-12):
            self.ramp_done = self.ramp_done or self.dt >= self.dt_max
            factor = RECOVERY_GROWTH if self.ramp_done else self.growth
            self.dt = min(self.dt * factor, self.dt_max)
        self.current_tol = min(self.current_tol * self.growth, self.tol)

    def rejected(self, dt: float) -> None:
        self.dt = 0.5 * dt
        if self.dt < 1e-14:
            raise RuntimeError(f"time step fell below 1e-14 s (dt = {self.dt:.3g})")



def fixed_step(t_end: float, dt: float, tol: float, stops: list[float] | None = None) -> RampedStep:
    """A constant dt, adjusted to t_end / round(t_end / dt) so that t_end is hit exactly.

    Steps still shorten to land on output times or to deposit a node, and halve on
    rejection; they return to dt afterwards.
    """
    dt = t_end / max(1, round(t_end / dt))
    return RampedStep(t_end=t_end, dt_init=dt, dt_max=dt, growth=1.0, tol=tol, tol_init=tol,
                      stops=stops or [])


def step_policy(config: Config) -> RampedStep:
    """The fixed step when ``time.dt`` is set, else the ramp of section 3.1."""
    tm, num = config.time, config.numerics
    if tm.dt is not None:
        return fixed_step(tm.t_end, tm.dt, num.tol, list(tm.output_times))
    return RampedStep(t_end=tm.t_end, dt_init=tm.dt_init, dt_max=tm.dt_max, growth=tm.dt_growth,
                      tol=num.tol, tol_init=num.tol_init or num.tol, stops=list(tm.output_times))
