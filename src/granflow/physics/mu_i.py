"""The mu(I) rheology of Jop, Forterre and Pouliquen (2006), regularised like (2.13).

mu(I) = mu_s + (mu_2 - mu_s) / (I0 / I + 1),   I = gamma_dot d / sqrt(P / rho_s),

with P = [p]_+ the pressure, d the grain diameter and rho_s the grain density (the bulk
density over rho_s is the packing fraction). The shear rate is written with the paper's
Frobenius norm: gamma_dot = sqrt(2) |Du| (simple shear u(z): |Du| = |u'| / sqrt(2), so
gamma_dot = |u'|). The stress is the law (2.13) with a rate-dependent yield stress,

    sigma' = 2 eta Du + sqrt(2) mu(I) P Du / sqrt(|Du|^2 + eps^2),

and gamma_dot is regularised as sqrt(2) sqrt(|Du|^2 + eps^2), so that the same Picard and
Newton paths apply. In simple shear the shear stress is eta u' + mu(I) P: the friction law
of Jop et al. plus the constant viscosity of the paper's law.

Where p vanishes (the free surface) I tends to infinity and mu to mu_2, but the yield
stress sqrt(2) mu P vanishes with P: the product is written as
mu_s P + (mu_2 - mu_s) P gamma_dot d / (I0 sqrt(P / rho_s) + gamma_dot d), finite at P = 0,
with sqrt(P / rho_s) regularised to sqrt(P / rho_s + (eps d)^2) so that Newton's tangent
stays finite there (the shift is eps d ~ 1e-9 m/s for eps = 1e-6 1/s, d = 1 mm).

Ill-posedness (Barker et al. 2015, J. Fluid Mech. 779, 794-818): incompressible mu(I) is
ill-posed at low and at high I. granflow keeps the constant viscosity eta of (2.13) (> 0 in
every configuration) beside mu(I), and a column run reports the inertial numbers its
flowing cells reach (summary.json ``inertial_number_flowing``: quantiles 5/50/95/99 % and the
largest, ``diagnostics/inertial.py``) and the share of them inside the law's well-posed
window (``physics/well_posedness.py``). With the paper's mu_s = tan 25.5 deg beside
mu_2 = tan 32.76 deg the law has no such window (C > 0 at every I), so the partial
regularisation of Barker and Gray (2017), which alters mu below the window, is not
implemented.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from granflow.physics.laws import Key, Law, named, packing_checks, register_rheology
from granflow.physics.ops import NUMPY_OPS, Ops


@dataclass(frozen=True)
class MuI:
    """mu(I) with the constant viscosity ``viscosity`` (Pa s) of (2.13) beside it.

    ``friction_angle_deg`` gives mu_s = tan(angle), ``mu_2_deg`` mu_2; ``i0`` is I0,
    ``grain_diameter`` d (m), ``grain_density`` rho_s (kg/m^3) and ``eps`` (1/s) the
    regularisation of (2.13).
    """

    viscosity: float
    friction_angle_deg: float
    mu_2_deg: float
    i0: float
    grain_diameter: float
    grain_density: float
    eps: float

    def __post_init__(self) -> None:
        if self.viscosity < 0:
            raise ValueError(f"viscosity = {self.viscosity}: must be >= 0")
        if not 0 <= self.friction_angle_deg < self.mu_2_deg < 90:
            raise ValueError(f"friction_angle_deg = {self.friction_angle_deg}, mu_2_deg = "
                             f"{self.mu_2_deg}: need 0 <= friction angle < mu_2 angle < 90")
        for name in ("i0", "grain_diameter", "grain_density", "eps"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} = {getattr(self, name)}: must be > 0")

    @property
    def mu_s(self) -> float:
        return math.tan(math.radians(self.friction_angle_deg))

    @property
    def mu_2(self) -> float:
        return math.tan(math.radians(self.mu_2_deg))

    def friction(self, inertial_number: Any) -> Any:
        """mu(I) = mu_s + (mu_2 - mu_s) I / (I0 + I) (numpy)."""
        return self.mu_s + (self.mu_2 - self.mu_s) * inertial_number / (
            self.i0 + inertial_number)

    def inverse_friction(self, mu: float) -> float:
        """The I with mu(I) = mu, for mu_s < mu < mu_2."""
        if not self.mu_s < mu < self.mu_2:
            raise ValueError(f"mu = {mu}: mu(I) only takes values in ({self.mu_s}, {self.mu_2})")
        return self.i0 * (mu - self.mu_s) / (self.mu_2 - mu)

    def inertial_number(self, shear_rate: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """I = gamma_dot d / sqrt(P / rho_s), gamma_dot = sqrt(2) |Du| (not regularised)."""
        return shear_rate * self.grain_diameter / ops.sqrt(
            ops.positive_part(pressure) / self.grain_density
            + (self.eps * self.grain_diameter) ** 2)

    def sliding_stress(self, slip_speed: Any, load: Any, ops: Ops = NUMPY_OPS) -> Any:
        """mu(I_b) P sliding at ``slip_speed`` over a bed of its own grains, I_b = slip /
        sqrt(P / rho_s) (``physics/bed.py``), written as the yield stress is: finite at
        P = 0."""
        load = ops.positive_part(load)
        root = ops.sqrt(load / self.grain_density + (self.eps * self.grain_diameter) ** 2)
        return self.mu_s * load + (self.mu_2 - self.mu_s) * load * slip_speed / (
            self.i0 * root + slip_speed)

    def yield_stress_sq(self, strain_rate_sq: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """kappa = sqrt(2) mu(I) [p]_+ at the regularised shear rate, finite at p = 0."""
        reg = ops.sqrt(strain_rate_sq + self.eps**2)
        shear = math.sqrt(2.0) * reg * self.grain_diameter     # gamma_dot d
        load = ops.positive_part(pressure)
        root = ops.sqrt(load / self.grain_density + (self.eps * self.grain_diameter) ** 2)
        mu_load = self.mu_s * load + (self.mu_2 - self.mu_s) * load * shear / (
            self.i0 * root + shear)
        return math.sqrt(2.0) * mu_load

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        """``m`` with sigma' = m Du: 2 eta + kappa(I) / sqrt(|Du|^2 + eps^2)."""
        kappa = self.yield_stress_sq(strain_rate_sq, pressure, ops)
        return 2.0 * self.viscosity + kappa / ops.sqrt(strain_rate_sq + self.eps**2)

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)


def _mu_i_checks(material: Any, section: str, eps: float) -> Iterator[str]:
    """mu_2 above mu_s, and grains at least as dense as the bulk."""
    delta = material.friction_angle_deg
    if material.mu_2_deg <= delta:
        yield (f"{section}.mu_2_deg = {material.mu_2_deg!r} must be greater than "
               f"{named(section, 'friction_angle_deg', 'friction angle', delta)} (mu(I) rises "
               "from mu_s to mu_2)")
    yield from packing_checks(material, section)


KEYS = {
    "mu_2_deg": Key(32.76, "mu(I): mu_2 = tan(angle), the friction at large I (Jop et al. "
                           "2006, glass beads)", low=0, below=90),
    "i0": Key(0.279, "mu(I): I0 (Jop et al. 2006)", low=1e-3, high=100,
              floor="mu rises to mu_2 over I ~ I0: below a thousandth it is mu_2 wherever "
                    "the material moves (glass beads: 0.279)"),
}

register_rheology(Law(
    "mu-i", KEYS,
    lambda m, eps, fields: MuI(viscosity=m.viscosity, friction_angle_deg=m.friction_angle_deg,
                               mu_2_deg=m.mu_2_deg, i0=m.i0, grain_diameter=m.grain_diameter,
                               grain_density=m.grain_density, eps=eps),
    _mu_i_checks, reads=("grain_diameter", "grain_density"), words="mu(I)"))
