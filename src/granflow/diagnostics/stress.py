"""The stress of the accepted state and how close it is to yield, from the solver's public
fields: sigma = sigma' - p Id (2.2) with the regularised sigma' = m(|Du|, p) Du of (2.13),
and the yield ratio |sigma'| / kappa, kappa = sqrt(2) mu_s [p]_+ (2.4): the material is
rigid where (2.3) holds, |sigma'| <= kappa, i.e. a ratio below 1; |.| is the Frobenius norm,
so in simple shear the ratio is tau / (mu_s p).
"""

from __future__ import annotations

import math
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.flow import FlowSolver
from granflow.physics.composite import blended
from granflow.physics.ops import Ops


def static_yield_stress(law: Any, pressure: Any, ops: Ops = NGSOLVE_OPS) -> Any:
    """kappa = sqrt(2) mu_s [p]_+ (2.4) with the law's static friction mu_s (mu(I)'s at
    I = 0); for a column over a layer of its own material, each material's; with a
    hysteretic friction, (1 - s) mu_start + s mu_s."""
    return blended(law, lambda part: math.sqrt(2.0) * part.mu_s * ops.positive_part(pressure))


def stress_components(solver: FlowSolver) -> dict[str, ngs.CoefficientFunction]:
    """The Cauchy stress sigma = m Du - p Id (Pa): its in-plane components xx, zz, xz (x
    along the bed, z normal to it; r, z for a cylinder, with the hoop component; all six
    in 3D), and
    |sigma'| = m |Du|, the Frobenius norm of its deviatoric part."""
    du = solver.coordinates.strain_rate(solver.velocity)
    m, p = solver.effective_viscosity(), solver.pressure
    if solver.coordinates.dimension == 3:      # x along the bed, y across, z normal to it
        out = {f"stress_{a}{b}": m * du[i, j] - (p if i == j else 0.0)
               for (i, a), (j, b) in (((0, "x"), (0, "x")), ((1, "y"), (1, "y")),
                                      ((2, "z"), (2, "z")), ((0, "x"), (1, "y")),
                                      ((0, "x"), (2, "z")), ((1, "y"), (2, "z")))}
        out["deviatoric_stress_norm"] = m * solver.strain_rate_norm()
        return out
    out = {"stress_xx": m * du[0, 0] - p, "stress_zz": m * du[1, 1] - p,
           "stress_xz": m * du[0, 1]}
    if solver.coordinates.axisymmetric:
        out["stress_hoop"] = m * du[2, 2] - p
    out["deviatoric_stress_norm"] = m * solver.strain_rate_norm()
    return out


def yield_ratio(deviatoric_norm: np.ndarray, yield_stress: np.ndarray) -> np.ndarray:
    """|sigma'| / kappa per cell (from cell means); NaN where kappa vanishes (no pressure,
    or no friction: a purely viscous material has no yield stress)."""
    kappa = np.asarray(yield_stress, dtype=float)
    ratio = np.full(kappa.shape, np.nan)
    positive = kappa > 0
    with np.errstate(over="ignore"):    # beyond the floats (kappa ~ 1e-300): inf, silently
        ratio[positive] = np.asarray(deviatoric_norm, dtype=float)[positive] / kappa[positive]
    return ratio
