"""Steady uniform flow of a nonlocal layer down a rough incline, solved in one dimension.

A layer of depth h on a slope theta, rough no-slip base Z = 0, free surface at Z = h: in
simple shear u(Z), p = P = rho g cos(theta) (h - Z) and the shear stress
tau = rho g sin(theta) (h - Z) balances (eta + P / g) gamma_dot (``physics/nonlocal_fluidity.py``,
sigma' = 2 eta Du + (2 P / g) Du), so gamma_dot = tau g / (P + eta g), and the steady
fluidity solves

    A^2 d^2 g'' + gamma_dot - (mu_s + b I) g = 0,   g(0) = 0,  g'(h) = 0,
    I = gamma_dot d / sqrt(P / rho_s)

(the solver's form of the fluidity equation without its eps-sized seed). Below the stopping
height the only solution is g = 0 (the layer at rest); above it a flowing branch exists.
With A = 0 it is the local law mu = mu_s + b I at every depth: Bagnold's profile.

Solved by finite volumes on a grid clustered at both ends (the base's condition and the
surface, where P -> 0) with Newton's method, independently of the 2D solver: the reference
for its steady profiles and the flow rule (the Froude number of the mean velocity).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import diags
from scipy.sparse.linalg import spsolve

from granflow.physics.nonlocal_fluidity import NonlocalFluidity
from granflow.reference.incline import SteadyProfile


@dataclass(frozen=True)
class NonlocalSteadyFlow:
    """The steady layer: Z, g(Z), u(Z) and the mean velocity; ``flowing`` is False when the
    Newton iteration found only the rest state g = 0."""

    z: np.ndarray
    fluidity: np.ndarray
    u: np.ndarray
    flowing: bool

    @property
    def profile(self) -> SteadyProfile:
        return SteadyProfile(self.z, self.u)

    @property
    def mean_velocity(self) -> float:
        return float(np.trapezoid(self.u, self.z) / (self.z[-1] - self.z[0]))


def _grid(height: float, points: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, points)
    return height * 0.5 * (1.0 - np.cos(math.pi * s))        # clustered at both ends


def steady_nonlocal_flow(*, law: NonlocalFluidity, height: float, slope_deg: float,
                         density: float, gravity: float = 9.81, points: int = 2001,
                         tol: float = 1e-12, max_iterations: int = 200) -> NonlocalSteadyFlow:
    """The steady flow of ``law`` (its fluidity field is not read) on the incline, from the
    local state g = g_loc(tan(theta)) by damped Newton iterations."""
    theta = math.radians(slope_deg)
    mu = math.tan(theta)
    z = _grid(height, points)
    depth = height - z
    pressure = density * gravity * math.cos(theta) * depth
    shear = density * gravity * math.sin(theta) * depth
    root = law.root_pressure(pressure)                           # sqrt(P / rho_s), regularised
    d, eta, diff = law.grain_diameter, law.viscosity, law.diffusivity
    # finite volumes: node i holds the cell between the midpoints around it
    mid = 0.5 * (z[1:] + z[:-1])
    width = np.diff(np.concatenate([[z[0]], mid, [z[-1]]]))
    conductance = diff / np.diff(z)                              # A^2 d^2 / dz per face
    base_fixed = law.amplitude > 0                               # g(0) = 0 when A > 0

    def rate(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        denominator = pressure + eta * g
        safe = np.where(denominator > 0, denominator, 1.0)
        value = np.where(denominator > 0, shear * g / safe, mu * g)
        slope = np.where(denominator > 0, (shear / safe) * (pressure / safe), mu)
        return value, slope

    def residual(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        gamma, dgamma = rate(g)
        inertial = gamma * d / root
        local = width * (gamma - (law.mu_s + law.b * inertial) * g)
        dlocal = width * (dgamma - law.mu_s - law.b * d / root * (dgamma * g + gamma))
        flux = conductance * np.diff(g)
        r = local.copy()
        r[:-1] += flux
        r[1:] -= flux
        return r, dlocal

    g = np.asarray(law.local_fluidity(mu, pressure), dtype=float) * np.ones_like(z)
    if base_fixed:
        g[0] = 0.0
    lower, upper = conductance.copy(), conductance.copy()
    for _ in range(max_iterations):
        r, dlocal = residual(g)
        main = dlocal.copy()
        main[:-1] -= conductance
        main[1:] -= conductance
        jac = diags([lower, main, upper], [-1, 0, 1], format="csr").tolil()
        if base_fixed:
            jac[0, :] = 0.0
            jac[0, 0] = 1.0
            r[0] = g[0]
        step = spsolve(jac.tocsr(), -r)
        damping = 1.0
        while damping > 1e-4:
            trial = np.maximum(g + damping * step, 0.0)
            if np.linalg.norm(residual(trial)[0][1:]) <= np.linalg.norm(r[1:]) or damping < 2e-4:
                break
            damping *= 0.5
        g = trial
        if np.max(np.abs(damping * step)) <= tol * max(np.max(np.abs(g)), 1e-300):
            break
    gamma, _ = rate(g)
    u = np.concatenate([[0.0], np.cumsum(0.5 * (gamma[1:] + gamma[:-1]) * np.diff(z))])
    flowing = bool(np.max(g) > 1e-8 * max(np.max(law.local_fluidity(mu, pressure)), 1e-300))
    return NonlocalSteadyFlow(z=z, fluidity=g, u=u, flowing=flowing)
