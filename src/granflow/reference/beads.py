"""The glass beads' measured laws on a rough incline, for validation (not used by any
solver): the stopping height and the flow rule of Pouliquen (1999, Phys. Fluids 11, 542) in
the fit of Forterre & Pouliquen (2003, J. Fluid Mech. 486, 21), whose constants go with the
mu(I) of Jop, Forterre & Pouliquen (2005, J. Fluid Mech. 541, 167):

    h_stop(theta) = L (tan(theta2) - tan(theta)) / (tan(theta) - tan(theta1)),
    Fr = u_mean / sqrt(g h cos(theta)) = beta h / h_stop(theta),

theta1 = 20.9 deg, theta2 = 32.76 deg, L = 1.65 d, beta = 0.136 (beads of d = 0.53 mm). With
Bagnold's profile (mean velocity (2/5) (I / d) sqrt(phi g cos(theta)) h^(3/2)) and mu(I) at
tan(theta) near theta1 the two laws give I0 = 5 beta d / (2 L sqrt(phi)): 0.279 at a packing
fraction phi = 0.545, the I0 of Jop et al.
"""

from __future__ import annotations

import math

THETA1_DEG = 20.9
THETA2_DEG = 32.76
LENGTH_PER_DIAMETER = 1.65
BETA = 0.136


def stopping_height(slope_deg: float, grain_diameter: float) -> float:
    """h_stop of the fit (m); infinite at or below theta1, zero at or above theta2."""
    t, t1, t2 = (math.tan(math.radians(a)) for a in (slope_deg, THETA1_DEG, THETA2_DEG))
    if t <= t1:
        return math.inf
    return max(LENGTH_PER_DIAMETER * grain_diameter * (t2 - t) / (t - t1), 0.0)


def froude(height: float, slope_deg: float, grain_diameter: float) -> float:
    """Pouliquen's flow rule Fr = beta h / h_stop(theta)."""
    return BETA * height / stopping_height(slope_deg, grain_diameter)
