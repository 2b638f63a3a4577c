"""Regularised Drucker–Prager viscoplastic law (paper eqs (2.2), (2.4), (2.13)).

Norms are the plain Frobenius norm, ``|D|^2 = sum_ij D_ij^2`` (no factor 1/2), which is
why the yield stress carries ``sqrt(2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

from granflow.physics.laws import Law, register_rheology
from granflow.physics.ops import NUMPY_OPS, Ops


class Rheology(Protocol):
    """A viscoplastic law sigma' = m(|Du|^2, p) Du, what the momentum forms need of it.

    ``m`` must be smooth in |Du|^2 (Newton differentiates it) and finite at Du = 0; laws:
    ``DruckerPrager`` (2.13) and ``MuI`` (physics/mu_i.py).
    """

    viscosity: float

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any: ...

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any: ...


@dataclass(frozen=True)
class DruckerPrager:
    """sigma' = 2 eta Du + kappa Du / sqrt(|Du|^2 + eps^2), kappa = sqrt(2) mu_s [p]_+.

    ``viscosity`` is the dynamic viscosity eta (Pa s), ``friction_angle_deg`` the internal
    friction angle delta (mu_s = tan delta) and ``eps`` the regularisation parameter (1/s).
    """

    viscosity: float
    friction_angle_deg: float
    eps: float

    def __post_init__(self) -> None:
        if self.viscosity < 0:
            raise ValueError(f"viscosity = {self.viscosity}: must be >= 0")
        if not 0 <= self.friction_angle_deg < 90:
            raise ValueError(f"friction_angle_deg = {self.friction_angle_deg}: must be in [0, 90)")
        if self.eps <= 0:
            raise ValueError(f"eps = {self.eps}: must be > 0")

    @property
    def mu_s(self) -> float:
        """Static internal friction coefficient tan(delta)."""
        return math.tan(math.radians(self.friction_angle_deg))

    def yield_stress(self, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """kappa = sqrt(2) mu_s [p]_+ (2.4)."""
        return math.sqrt(2.0) * self.mu_s * ops.positive_part(pressure)

    def sliding_stress(self, slip_speed: Any, load: Any, ops: Ops = NUMPY_OPS) -> Any:
        """mu_s [load]_+: the stress it exerts sliding over a bed of its own grains, at any
        speed (``physics/bed.py``)."""
        return self.mu_s * ops.positive_part(load)

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        """The factor ``m`` with sigma' = m Du in (2.13): 2 eta + kappa / sqrt(|Du|^2 + eps^2).

        Finite at Du = 0 (it equals 2 eta + kappa / eps there); this is the coefficient the
        fixed-point iteration (3.2a) freezes at the previous iterate.
        """
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        """``m`` of (2.13) from |Du|^2: smooth at Du = 0, so Newton can differentiate it
        (sqrt(|Du|^2)^2 has an infinite derivative there)."""
        kappa = self.yield_stress(pressure, ops)
        return 2.0 * self.viscosity + kappa / ops.sqrt(strain_rate_sq + self.eps**2)

    def deviatoric_stress(self, strain_rate: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """sigma'_eps (2.13) for a strain-rate tensor given as a numpy array (..., 2, 2)."""
        import numpy as np

        norm = np.sqrt(np.sum(np.asarray(strain_rate) ** 2, axis=(-2, -1)))
        m = self.effective_viscosity(norm, pressure, ops)
        return np.asarray(m)[..., None, None] * strain_rate


register_rheology(Law("drucker-prager", {}, lambda m, eps, fields: DruckerPrager(
    viscosity=m.viscosity, friction_angle_deg=m.friction_angle_deg, eps=eps),
    words="Drucker-Prager (2.13)"))
