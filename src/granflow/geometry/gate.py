"""A gate: a wall on the mass's front face, withdrawn along itself at a prescribed speed.

The laboratory columns are released by lifting a gate (Lusso et al., section 5.3: a gate
inclined at 70 degrees for the trapezoid, perpendicular to the channel base for the
rectangle). Its speed history is constant, U, or U_inf (1 - exp(-t / tau)) (the door of
Sarlin et al. 2021 and Rousseau et al. 2023, about 0.7 m/s and 0.13 s for glass beads).
The gate's lower end has then risen by the opening s(t), the integral of the speed; the
front face below it is free surface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from granflow.geometry.profile import Line

MAX_SPEED = 50.0   # m/s: faster than any laboratory gate (an instantaneous release)


@dataclass(frozen=True)
class GateLaw:
    """The speed history of the gate: "constant" U, or "exponential" U (1 - exp(-t/tau))."""

    kind: str
    speed: float          # U, or U_inf (m/s)
    tau: float = 0.0      # s, the exponential law's time scale

    def velocity(self, t: float) -> float:
        """Speed of the gate at time t (m/s)."""
        if self.kind == "constant":
            return self.speed
        return self.speed * -math.expm1(-t / self.tau)

    def opening(self, t: float) -> float:
        """How far the gate's lower end has risen at time t: the integral of the speed."""
        if self.kind == "constant":
            return self.speed * t
        return self.speed * (t + self.tau * math.expm1(-t / self.tau))

    def open_time(self, height: float) -> float:
        """When the opening reaches ``height`` (the gate has cleared the mass)."""
        if self.kind == "constant":
            return height / self.speed
        lo, hi = 0.0, height / self.speed + self.tau
        for _ in range(80):                  # opening(t) is increasing: bisection
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if self.opening(mid) < height else (lo, mid)
        return hi


@dataclass(frozen=True)
class Gate:
    """The gate's line (through the foot of the mass's front face, pointing up along it,
    ``inner`` towards the mass), the height of that face, its law and its friction."""

    line: Line
    height: float
    law: GateLaw
    friction_deg: float

    def velocity_vector(self, t: float) -> tuple[float, float]:
        """The gate's velocity at time t: along its line, upwards."""
        u = self.law.velocity(t)
        return (u * self.line.direction[0], u * self.line.direction[1])

    def closed(self, xy: np.ndarray, t: float) -> np.ndarray:
        """Whether points of the gate's line are above its lower end at time t."""
        return self.line.along(xy) > self.law.opening(t)
