"""Steady uniform flow of a layer down an incline steeper than its friction: exact profiles.

A layer of depth h on a slope theta, no slip at the bed Z = 0 and a free surface at Z = h,
flows steadily when the shear stress rho g sin(theta) (h - Z) is balanced by the law's
shear stress. In simple shear u(Z), p = rho g cos(theta) (h - Z) (sigma'_ZZ = 0) and both
laws give a shear stress eta u' + mu p (section physics: |Du| = u' / sqrt(2), so
sqrt(2) mu p Du_XZ / |Du| = mu p):

- Drucker-Prager (2.13) with constant mu_s < tan(theta): the parabola
  u = rho g (sin(theta) - mu_s cos(theta)) / eta (h Z - Z^2 / 2);
- mu(I) with mu_s < tan(theta) < mu_2 and eta = 0: the Bagnold profile
  u = (2/3) (I_theta / d) sqrt(phi g cos(theta)) (h^(3/2) - (h - Z)^(3/2)),
  mu(I_theta) = tan(theta), phi = rho / rho_s (the packing fraction);
  with eta > 0 the shear rate solves eta u' + mu(I) p = rho g sin(theta) (h - Z) at each
  depth (a scalar root, ``mu_i_profile``), which tends to Bagnold's as eta -> 0.

The regularisation eps of (2.13) is not in these profiles: they are the laws' exact
unregularised solutions, against which the 2D runs are measured.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from granflow.physics import MuI
from granflow.reference.plug1d import profile_at


@dataclass(frozen=True)
class SteadyProfile:
    """u(Z) on a fine grid of [0, h]; called like the 1D plug-flow reference."""

    z: np.ndarray
    u: np.ndarray
    interface: float | None = None     # no plug: the whole layer shears

    def __call__(self, z: np.ndarray | float) -> np.ndarray:
        return profile_at(self.z, self.u, z)


def _grid(height: float, points: int) -> np.ndarray:
    # clustered towards the surface, where the mu(I) shear rate varies like sqrt(h - Z)
    s = np.linspace(0.0, 1.0, points)
    return height * (1.0 - (1.0 - s) ** 2)


def drucker_prager_profile(*, height: float, slope_deg: float, friction_angle_deg: float,
                           viscosity: float, density: float, gravity: float = 9.81,
                           points: int = 2001) -> SteadyProfile:
    """The parabola of the Drucker-Prager layer steeper than its friction angle."""
    theta, mu_s = math.radians(slope_deg), math.tan(math.radians(friction_angle_deg))
    drive = math.sin(theta) - mu_s * math.cos(theta)
    if drive <= 0:
        raise ValueError(f"slope {slope_deg} deg is not steeper than the friction angle "
                         f"{friction_angle_deg} deg: the layer has no steady flow")
    z = _grid(height, points)
    return SteadyProfile(z, density * gravity * drive / viscosity * (height * z - z**2 / 2))


def bagnold_profile(*, height: float, slope_deg: float, law: MuI, density: float,
                    gravity: float = 9.81, points: int = 2001) -> SteadyProfile:
    """Bagnold's profile of mu(I) without viscosity (the exact solution for eta = 0)."""
    i_theta = law.inverse_friction(math.tan(math.radians(slope_deg)))
    return bagnold(height=height, slope_deg=slope_deg, inertial_number=i_theta,
                   grain_diameter=law.grain_diameter,
                   packing=density / law.grain_density, gravity=gravity, points=points)


def bagnold(*, height: float, slope_deg: float, inertial_number: float,
            grain_diameter: float, packing: float, gravity: float = 9.81,
            points: int = 2001) -> SteadyProfile:
    """Bagnold's profile of any local law whose friction is tan(theta) at ``inertial_number``
    I_theta: u = (2/3) (I_theta / d) sqrt(phi g cos(theta)) (h^(3/2) - (h - Z)^(3/2))."""
    theta = math.radians(slope_deg)
    z = _grid(height, points)
    u = (2.0 / 3.0) * (inertial_number / grain_diameter) * math.sqrt(
        packing * gravity * math.cos(theta)) * (height**1.5 - (height - z) ** 1.5)
    return SteadyProfile(z, u)


def mu_i_profile(*, height: float, slope_deg: float, law: MuI, density: float,
                 gravity: float = 9.81, points: int = 2001) -> SteadyProfile:
    """The steady mu(I) profile with the constant viscosity ``law.viscosity`` beside mu(I):
    at each depth s = h - Z the shear rate solves eta g + mu(I(g)) p = rho g sin(theta) s."""
    theta = math.radians(slope_deg)
    law.inverse_friction(math.tan(theta))          # raises unless mu_s < tan(theta) < mu_2
    z = _grid(height, points)
    rates = np.zeros_like(z)
    for k, s in enumerate(height - z):
        if s <= 0:
            continue
        pressure = density * gravity * math.cos(theta) * s
        shear_stress = density * gravity * math.sin(theta) * s
        root = math.sqrt(pressure / law.grain_density)

        def excess(rate: float, pressure: float = pressure, root: float = root,
                   shear_stress: float = shear_stress) -> float:
            friction = law.friction(rate * law.grain_diameter / root)
            return law.viscosity * rate + friction * pressure - shear_stress

        upper = 1.0
        while excess(upper) < 0:
            upper *= 2.0
        rates[k] = brentq(excess, 0.0, upper, xtol=1e-14, rtol=1e-13)
    # u(Z) = int_0^Z rate dZ' (trapezoid rule on the clustered grid: error << 1e-5)
    u = np.concatenate([[0.0], np.cumsum(0.5 * (rates[1:] + rates[:-1]) * np.diff(z))])
    return SteadyProfile(z, u)
