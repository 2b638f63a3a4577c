"""Time-step policies: a fixed step, and the paper's ramp (section 3.1)."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class FixedStep:
    """Constant dt, adjusted to t_end / round(t_end / dt) so that t_end is hit exactly."""

    t_end: float
    dt: float
    tol: float
    n_steps: int = field(init=False)

    def __post_init__(self) -> None:
        self.n_steps = max(1, round(self.t_end / self.dt))
        self.dt = self.t_end / self.n_steps

    def propose(self, t: float) -> tuple[float, float]:
        return min(self.dt, self.t_end - t), self.tol

    def accepted(self, dt: float) -> None:
        pass

    def rejected(self, dt: float) -> None:
        raise RuntimeError("a fixed time step cannot be reduced; use the ramp (time.dt unset)")


@dataclass
class RampedStep:
    """dt_{n+1} = growth * dt_n from dt_init up to dt_max; tol ramps likewise (3.1).

    A rejected step halves dt (and restarts the growth from there). Steps are clipped so
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
        if dt >= self.dt * (1 - 1e-12):
            self.dt = min(self.dt * self.growth, self.dt_max)
            self.current_tol = min(self.current_tol * self.growth, self.tol)

    def rejected(self, dt: float) -> None:
        self.dt = 0.5 * dt
        if self.dt < 1e-14:
            raise RuntimeError(f"time step fell below 1e-14 s (dt = {self.dt:.3g})")

