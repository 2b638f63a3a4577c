"""Time-step policies: the paper's ramp (section 3.1), a fixed step, and adaptive steps
with local error control.

A policy proposes (dt, tol) for the next attempt, judges a converged step from its local
error estimate, and learns from accepted and rejected attempts. Every policy clips steps so
that its ``stops`` (output times, t_end) are hit exactly; the mesh motion may shorten a
step further (deposition, Figure 2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Annotated

from granflow.state.spec import POSITIVE, TIME, list_of, number, or_none, whole

if TYPE_CHECKING:
    from granflow.config import Config


# what a policy's numbers may be in a checkpoint (``state/spec.py: dataclass_of``): a
# NaN or negative step, tolerance or stop is refused before the run goes on
Positive = Annotated[float, POSITIVE]
Stops = Annotated[list[float], list_of(TIME)]


@dataclass(frozen=True)
class LocalError:
    """Estimated local error of the velocity over one step and the velocity scale, both as
    root-mean-square speeds over the domain (m/s)."""

    error: float
    speed: float

RECOVERY_GROWTH = 2.0  # regrowth of dt after a rejected step, up to the ramp's current dt
REJECTION_FACTOR = 0.5  # dt after a step whose nonlinear solve failed
DT_FLOOR = 1e-14       # s: below this a run cannot make progress


class StepTooSmall(RuntimeError):
    """The step size fell below DT_FLOOR."""


def _clip_to_stops(t: float, dt: float, stops: list[float]) -> float:
    for stop in stops:
        if stop > t + 1e-14:
            if t + dt > stop - 1e-12 * max(1.0, stop):
                dt = stop - t
            break
    return dt


def _stops(stops: list[float], t_end: float) -> list[float]:
    return sorted({s for s in stops if 0 < s < t_end} | {t_end})


@dataclass
class RampedStep:
    """dt_{n+1} = growth * dt_n from dt_init up to dt_max; tol ramps likewise (section 3.1).

    A rejected step halves dt. The ramp's own dt (``dt``) is kept apart from the reduced
    step that follows a rejection (``recovering``), which then doubles back up to it on each
    accepted step: a fixed step that was halved once returns to its size.
    """

    t_end: Positive
    dt_init: Positive
    dt_max: Positive
    growth: Annotated[float, number(1.0)]
    tol: Positive
    tol_init: Positive
    stops: Stops = field(default_factory=list)
    step_key: str = "time.dt_max"     # the key a user changes to shorten the steps
    dt: Positive = field(init=False)
    recovering: Annotated[float | None, or_none(POSITIVE)] = field(init=False, default=None)
    current_tol: Positive = field(init=False)

    def __post_init__(self) -> None:
        self.dt = min(self.dt_init, self.dt_max)
        self.current_tol = min(self.tol_init, self.tol)
        self.stops = _stops(self.stops, self.t_end)

    @property
    def next_dt(self) -> float:
        return self.dt if self.recovering is None else self.recovering

    def propose(self, t: float) -> tuple[float, float]:
        return _clip_to_stops(t, self.next_dt, self.stops), self.current_tol

    def judge(self, estimate: LocalError | None) -> bool:
        """The ramp accepts every converged step (the paper has no error control)."""
        return True

    def accepted(self, dt: float, estimate: LocalError | None = None,
                 restarted: bool = False) -> None:
        """Grow dt after a full step; a step shortened by a stop or a landing keeps dt (the
        ramp ignores a restarted history)."""
        if self.recovering is not None:
            if dt >= self.recovering * (1 - 1e-12):
                grown = self.recovering * RECOVERY_GROWTH
                self.recovering = None if grown >= self.dt else grown
        elif dt >= self.dt * (1 - 1e-12):
            self.dt = min(self.dt * self.growth, self.dt_max)
        self.current_tol = min(self.current_tol * self.growth, self.tol)

    def rejected(self, dt: float, estimate: LocalError | None = None) -> None:
        self.recovering = REJECTION_FACTOR * dt
        if self.recovering < DT_FLOOR:
            raise StepTooSmall(f"time step fell below {DT_FLOOR:g} s "
                               f"(dt = {self.recovering:.3g} s)")


SAFETY = 0.9       # of the step the error estimate predicts
MAX_GROWTH = 2.0   # per accepted step
MIN_SHRINK = 0.2   # per rejected or accepted step


@dataclass
class AdaptiveStep:
    """Steps sized by a local error estimate (elementary controller).

    The error of a step is its estimated local velocity error (``FlowSolver.local_error``)
    over error_tol * max(RMS speed, error_floor): a step is accepted when it is at most 1,
    and the next dt is dt * SAFETY / error^(1/(q+1)) for a scheme of order q (the local
    error grows as dt^(q+1): sqrt for implicit Euler), kept within
    [MIN_SHRINK, MAX_GROWTH] times the last step and within [dt_min, dt_max]. A step whose
    nonlinear solve failed is retried at half its size. Steps shortened by a stop or a
    landing do not shrink the controller's dt unless their error asks for it.

    With ``dt_max_slow`` above dt_max, the cap rises while the flow is slow: to the step
    in which the flow's RMS speed (of the last accepted step) carries it ``slow_travel``
    (m), between dt_max and dt_max_slow. A fast flow keeps dt_max.
    """

    t_end: Positive
    dt_init: Positive
    dt_max: Positive
    tol: Positive
    error_tol: Positive
    error_floor: Positive
    stops: Stops = field(default_factory=list)
    dt_min: Positive = DT_FLOOR
    step_key: str = "time.error_tol or time.dt_max"
    order: Annotated[int, whole(1)] = 1      # of the time scheme
    dt_max_slow: Annotated[float, TIME] = 0.0   # s: the cap of a slow flow (at most dt_max: off)
    slow_travel: Annotated[float, TIME] = 0.0   # m: a step that carries the flow this far is slow
    dt: Positive = field(init=False)
    cap: Annotated[float, TIME] = field(init=False, default=0.0)  # the largest step now (0: dt_max)

    def __post_init__(self) -> None:
        self.dt = min(self.dt_init, self.dt_max)
        self.stops = _stops(self.stops, self.t_end)
        self.cap = self.dt_max

    def _cap(self, estimate: LocalError | None) -> float:
        """dt_max, or while the flow is slow a larger cap (class docstring)."""
        if self.dt_max_slow <= self.dt_max:
            return self.dt_max
        if estimate is None:
            return self.cap if self.cap > 0 else self.dt_max
        reach = self.slow_travel / estimate.speed if estimate.speed > 0 else math.inf
        return min(self.dt_max_slow, max(self.dt_max, reach))

    @property
    def next_dt(self) -> float:
        return self.dt

    def propose(self, t: float) -> tuple[float, float]:
        return _clip_to_stops(t, self.dt, self.stops), self.tol

    def error(self, estimate: LocalError | None) -> float | None:
        """The step's error relative to its tolerance (None without an estimate)."""
        if estimate is None:
            return None
        return estimate.error / (self.error_tol * max(estimate.speed, self.error_floor))

    def judge(self, estimate: LocalError | None) -> bool:
        error = self.error(estimate)
        return error is None or error <= 1.0

    def _factor(self, error: float | None) -> float:
        if error is None:
            return MAX_GROWTH
        if not math.isfinite(error):
            return MIN_SHRINK
        if error <= 0:
            return MAX_GROWTH
        root = math.sqrt(error) if self.order == 1 else error ** (1.0 / (self.order + 1))
        return min(MAX_GROWTH, max(MIN_SHRINK, SAFETY / root))

    def accepted(self, dt: float, estimate: LocalError | None = None,
                 restarted: bool = False) -> None:
        """The next dt from the step's error; a step that restarted the history has no
        estimate and keeps dt (its size says nothing about the error after the jump)."""
        unknown = restarted and estimate is None
        factor = 1.0 if unknown else self._factor(self.error(estimate))
        full = dt >= self.dt * (1 - 1e-12)
        if full or factor < 1.0:
            proposed = dt * factor
            self.dt = proposed if full else min(self.dt, proposed)
        self.cap = self._cap(estimate)
        self.dt = min(max(self.dt, self.dt_min), self.cap)

    def rejected(self, dt: float, estimate: LocalError | None = None) -> None:
        """estimate None: the nonlinear solve failed; else the step's error was too large."""
        error = self.error(estimate)
        factor = REJECTION_FACTOR if error is None else min(self._factor(error), 0.9)
        self.dt = dt * factor
        if self.dt < max(self.dt_min, DT_FLOOR):
            raise StepTooSmall(f"time step fell below {max(self.dt_min, DT_FLOOR):g} s "
                               f"(dt = {self.dt:.3g} s)")


StepPolicy = RampedStep | AdaptiveStep


def fixed_step(t_end: float, dt: float, tol: float, stops: list[float] | None = None) -> RampedStep:
    """A constant dt, adjusted to t_end / round(t_end / dt) so that t_end is hit exactly.

    Steps still shorten to land on output times or to deposit a node, and halve on
    rejection; they return to dt afterwards.
    """
    dt = t_end / max(1, round(t_end / dt))
    return RampedStep(t_end=t_end, dt_init=dt, dt_max=dt, growth=1.0, tol=tol, tol_init=tol,
                      stops=stops or [], step_key="time.dt")


def step_policy(config: Config) -> StepPolicy:
    """The fixed step when ``time.dt`` is set, the error-controlled step when
    ``time.adaptive``, else the ramp of section 3.1."""
    tm, num = config.time, config.numerics
    stops = list(tm.output_times)
    if tm.dt is not None:
        return fixed_step(tm.t_end, tm.dt, num.tol, stops)
    if tm.adaptive:
        return AdaptiveStep(t_end=tm.t_end, dt_init=tm.dt_init, dt_max=tm.dt_max, tol=num.tol,
                            error_tol=tm.error_tol, error_floor=tm.error_floor, stops=stops,
                            order=2 if tm.scheme == "bdf2" else 1,
                            dt_max_slow=tm.dt_max_slow or 0.0,
                            slow_travel=tm.slow_courant * config.mesh.size)
    return RampedStep(t_end=tm.t_end, dt_init=tm.dt_init, dt_max=tm.dt_max, growth=tm.dt_growth,
                      tol=num.tol, tol_init=num.tol_start, stops=stops)
