"""Gravity in the bed-aligned frame."""

from __future__ import annotations

import math


def gravity_vector(gravity: float, slope_deg: float) -> tuple[float, float]:
    """f = (g sin theta, -g cos theta) in the bed-aligned frame (X, Z) (section 2.1)."""
    theta = math.radians(slope_deg)
    return gravity * math.sin(theta), -gravity * math.cos(theta)


def gravity_vector_3d(gravity: float, slope_deg: float) -> tuple[float, float, float]:
    """f = (g sin theta, 0, -g cos theta) in the bed-aligned frame (X, Y, Z), Y across the
    slope."""
    along, normal = gravity_vector(gravity, slope_deg)
    return along, 0.0, normal
