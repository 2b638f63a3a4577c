"""Where incompressible mu(I) is well posed: the criterion of Barker and Gray (2017).

Barker, Schaeffer, Bohorquez and Gray (2015, J. Fluid Mech. 779) showed that the
incompressible mu(I) equations are ill posed (short waves grow without bound) wherever

    C(I) = 4 nu^2 - 4 nu + mu^2 (1 - nu / 2)^2 > 0,    nu = I mu'(I) / mu(I),

in the form of Barker and Gray (2017, J. Fluid Mech. 828, eq. 3.9). As I -> 0 and as
I -> infinity, nu -> 0 and C -> mu^2 > 0: the law is ill posed at low and at high I. Where
C < 0 for some I it is well posed in a window I_N1 < I < I_N2 (Barker and Gray regularise
mu below I_N1, which needs the window to exist). This module finds the window of a law.

The criterion is that of mu(I) alone: granflow's law (2.13) keeps the constant viscosity
eta beside mu(I) P, a stress that is not a function of I only, which the analysis does
not cover.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy.optimize import brentq

from granflow.physics.mu_i import MuI

I_RANGE = (1e-9, 1e4)   # the window is searched over these inertial numbers


def friction_slope(law: MuI, inertial_number: Any) -> Any:
    """mu'(I) = (mu_2 - mu_s) I0 / (I0 + I)^2."""
    return (law.mu_2 - law.mu_s) * law.i0 / (law.i0 + inertial_number) ** 2


def ill_posedness(law: MuI, inertial_number: Any) -> Any:
    """C(I) of Barker and Gray (2017, eq. 3.9): ill posed where C > 0, well posed where C < 0."""
    mu = law.friction(inertial_number)
    nu = inertial_number * friction_slope(law, inertial_number) / mu
    return 4.0 * nu**2 - 4.0 * nu + mu**2 * (1.0 - nu / 2.0) ** 2


def _scan(law: MuI, samples: int) -> tuple[np.ndarray, np.ndarray]:
    """C on ``samples`` log-spaced inertial numbers over I_RANGE."""
    grid = np.logspace(np.log10(I_RANGE[0]), np.log10(I_RANGE[1]), samples)
    return grid, ill_posedness(law, grid)


def well_posed_window(law: MuI, samples: int = 4001) -> tuple[float, float] | None:
    """(I_N1, I_N2) where C < 0, each bound to a relative 1e-10; None if C >= 0 for every I
    in I_RANGE (ill posed everywhere)."""
    grid, values = _scan(law, samples)
    negative = np.flatnonzero(values < 0)
    if len(negative) == 0:
        return None
    first, last = negative[0], negative[-1]
    if first == 0 or last == len(grid) - 1:
        raise ValueError("mu(I) is well posed at the end of the searched range "
                         f"{I_RANGE}: not the mu(I) of Jop et al. (2006)")

    def crossing(a: float, b: float) -> float:
        return float(brentq(lambda i: ill_posedness(law, i), a, b, rtol=1e-10))

    return (crossing(grid[first - 1], grid[first]), crossing(grid[last], grid[last + 1]))


def smallest_ill_posedness(law: MuI, samples: int = 4001) -> tuple[float, float]:
    """(min C, the I where it is reached) over I_RANGE: how far the law is from a window."""
    grid, values = _scan(law, samples)
    k = int(np.argmin(values))
    return float(values[k]), float(grid[k])
