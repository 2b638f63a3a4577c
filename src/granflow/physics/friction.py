"""Regularised Coulomb friction on the bed and the wall (paper eqs (2.8), (2.17a))."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from granflow.physics.ops import NUMPY_OPS, Ops


@dataclass(frozen=True)
class CoulombFriction:
    """Tangential traction -mu u_T / sqrt(|u_T|^2 + eps_f^2) [p - sigma'_N]_+ (2.17a).

    ``friction_angle_deg`` gives mu = tan(angle); ``eps_friction`` (m/s) regularises the
    sign of the slip velocity.
    """

    friction_angle_deg: float
    eps_friction: float

    def __post_init__(self) -> None:
        if not 0 <= self.friction_angle_deg < 90:
            raise ValueError(
                f"friction_angle_deg = {self.friction_angle_deg}: must be in [0, 90)")
        if self.eps_friction <= 0:
            raise ValueError(f"eps_friction = {self.eps_friction}: must be > 0")

    @property
    def mu(self) -> float:
        """Coulomb coefficient tan(angle)."""
        return math.tan(math.radians(self.friction_angle_deg))

    def drag_coefficient(self, slip_speed: Any, normal_stress: Any,
                         ops: Ops = NUMPY_OPS) -> Any:
        """Factor c with traction = -c u_T: mu [p - sigma'_N]_+ / sqrt(|u_T|^2 + eps_f^2).

        ``normal_stress`` is the compressive normal load p - sigma'_N; the fixed-point
        iteration (3.2a) evaluates both arguments at the previous iterate.
        """
        return self.drag_coefficient_sq(slip_speed**2, normal_stress, ops)

    def drag_coefficient_sq(self, slip_sq: Any, normal_stress: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        """``drag_coefficient`` from |u_T|^2, smooth at u_T = 0 (for Newton's tangent)."""
        return self.mu * ops.positive_part(normal_stress) / ops.sqrt(
            slip_sq + self.eps_friction**2)


@dataclass(frozen=True)
class SideWallFriction:
    """Coulomb drag of the two side walls of a channel of width W, averaged across it.

    Each wall presses on the material with the pressure p (isotropic stress, the closure of
    Jop, Forterre and Pouliquen 2005, J. Fluid Mech. 541, 167-192) and resists its motion
    with mu_w p; over the width this is the body force -(2 mu_w / W) [p]_+ u / |u|,
    regularised by eps_f like (2.17a).
    """

    channel_width: float
    friction_angle_deg: float
    eps_friction: float

    def __post_init__(self) -> None:
        if self.channel_width <= 0:
            raise ValueError(f"channel_width = {self.channel_width}: must be > 0")
        CoulombFriction(self.friction_angle_deg, self.eps_friction)   # same checks

    def drag_coefficient_sq(self, speed_sq: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """c with body force -c u: (2 / W) mu_w [p]_+ / sqrt(|u|^2 + eps_f^2)."""
        wall = CoulombFriction(self.friction_angle_deg, self.eps_friction)
        return 2.0 / self.channel_width * wall.drag_coefficient_sq(speed_sq, pressure, ops)
