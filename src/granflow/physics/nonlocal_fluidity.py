"""The nonlocal granular fluidity model (Kamrin & Koval 2012, Phys. Rev. Lett. 108, 178301;
Henann & Kamrin 2013, PNAS 110, 6730) in its nonlinear dynamic form (Henann & Kamrin 2014,
Int. J. Plasticity 60, 145; Kamrin & Henann 2015, Soft Matter 11, 179; Zhang & Kamrin 2017,
Phys. Rev. Lett. 118, 058001).

A scalar field, the granular fluidity g (1/s), sets the flow rule gamma_dot = g mu, with
gamma_dot = sqrt(2) |Du| (|u'| in simple shear, the paper's Frobenius norm) and mu the stress
ratio |sigma'| / (sqrt(2) P), P = [p]_+. As a viscous law, sigma' = (2 P / g) Du. It evolves as

    t0 Dg/Dt = A^2 d^2 lap g - (mu_s - mu) g - b mu sqrt(rho_s d^2 / P) g^2,

with d the grain diameter, rho_s the grain density, A the nonlocal amplitude, b the slope of
the local law and t0 a time scale. Its homogeneous steady state is g = gamma_dot / (mu_s + b I),
I = gamma_dot d / sqrt(P / rho_s): the local law mu = mu_s + b I (the linear mu(I) of the
beads' calibration, b = (mu_2 - mu_s) / I0). Its rest state g = 0 is an exact solution; on an
incline it loses stability only in a layer thicker than

    h_stop = (pi / 2) A d / sqrt(tan(theta) - mu_s)

(g = 0 at a rough base, zero flux at the free surface: the quarter wave of A^2 d^2 g'' +
(tan(theta) - mu_s) g = 0), which is the model's stopping height. The linear steady form of
Kamrin & Koval has no such threshold.

Regularisation. Where g vanishes the viscosity 2 P / g is infinite; the law uses g + g_eps
with g_eps = sqrt(2) eps / mu_s, so that material at rest has exactly the viscosity of the
regularised Drucker-Prager law (2.13) at rest, sqrt(2) mu_s P / eps, and creeps at its rate
(order eps). With gamma_dot = mu (g + g_eps) the two stress-ratio terms read
mu g = gamma_dot - mu g_eps and b mu sqrt(rho_s d^2 / P) g^2 = b I g (g / (g + g_eps)); the
solver (``fem/fluidity.py``) uses

    t0 Dg/Dt = A^2 d^2 lap g + gamma_dot - (mu_s + b I) g,

which differs from the form above by g_eps (mu - b I g / (g + g_eps)): the creep's own
fluidity, which seeds the instability of material at rest as a perturbation of size eps
would, and vanishes with eps. It is linear in g for a given flow, and g >= 0.

The time scale. Neither the stopping height nor any steady state depends on t0, which only
sets how fast g relaxes. The fluidity is a kinematic measure of the velocity fluctuations
(Zhang & Kamrin 2017), which relax by collisions on the model's only microscopic time, the
inertial time d sqrt(rho_s / P) of I; ``fluidity_time = "inertial"`` takes it (P regularised
as in mu(I), ``physics/mu_i.py``), a number takes a constant t0 (s).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from granflow.physics.laws import Key, Law, LawFields, packing_checks, register_rheology
from granflow.physics.ops import NUMPY_OPS, Ops

INERTIAL = "inertial"


@dataclass(frozen=True)
class NonlocalFluidity:
    """The ``Rheology`` sigma' = 2 eta Du + (2 P / (g + g_eps)) Du of the fluidity ``fluidity``
    (a number, an array or a finite-element coefficient function: the field the law reads
    during a step), and the coefficients of its equation (module docstring)."""

    viscosity: float
    friction_angle_deg: float
    b: float
    amplitude: float
    grain_diameter: float
    grain_density: float
    eps: float
    time: str | float = INERTIAL
    fluidity: Any = 0.0
    friction_cap_deg: float | None = None     # mu_max = tan(angle); None: no cap

    def __post_init__(self) -> None:
        if self.viscosity < 0:
            raise ValueError(f"viscosity = {self.viscosity}: must be >= 0")
        if not 0 < self.friction_angle_deg < 90:
            raise ValueError(f"friction_angle_deg = {self.friction_angle_deg}: must be in "
                             "(0, 90) (g_eps = sqrt(2) eps / mu_s)")
        for name in ("b", "grain_diameter", "grain_density", "eps"):
            if getattr(self, name) <= 0:
                raise ValueError(f"{name} = {getattr(self, name)}: must be > 0")
        if self.amplitude < 0:
            raise ValueError(f"amplitude = {self.amplitude}: must be >= 0")
        if self.time != INERTIAL and not (isinstance(self.time, (int, float))
                                          and self.time > 0):
            raise ValueError(f"time = {self.time!r}: must be 'inertial' or a number > 0")

    @property
    def mu_s(self) -> float:
        return math.tan(math.radians(self.friction_angle_deg))

    @property
    def floor(self) -> float:
        """g_eps = sqrt(2) eps / mu_s: the fluidity of the regularised law's rest state."""
        return math.sqrt(2.0) * self.eps / self.mu_s

    @property
    def diffusivity(self) -> float:
        """A^2 d^2 (m^2), the coefficient of lap g."""
        return (self.amplitude * self.grain_diameter) ** 2

    # --- the flow rule ------------------------------------------------------------------
    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        """``m`` with sigma' = m Du: 2 eta + 2 P / ([g]_+ + g_eps); it does not depend on the
        strain rate (the fluidity is a given field during a step)."""
        load = ops.positive_part(pressure)
        fluidity = ops.positive_part(self.fluidity) + self.floor
        if self.friction_cap_deg is not None:        # at least gamma_dot / mu_max
            capped = math.sqrt(2.0) * ops.sqrt(strain_rate_sq + self.eps**2) / math.tan(
                math.radians(self.friction_cap_deg))
            fluidity = fluidity + ops.positive_part(capped - fluidity)
        return 2.0 * self.viscosity + 2.0 * load / fluidity

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)

    def sliding_stress(self, slip_speed: Any, load: Any, ops: Ops = NUMPY_OPS) -> Any:
        """(mu_s + b I_b) P sliding at ``slip_speed`` over a bed of its own grains, I_b =
        slip / sqrt(P / rho_s) (``physics/bed.py``): the local law, at most mu_2 P where the
        law has its cap."""
        load = ops.positive_part(load)
        local = self.mu_s * load + self.b * slip_speed * load / self.root_pressure(load, ops)
        if self.friction_cap_deg is None:
            return local
        cap = math.tan(math.radians(self.friction_cap_deg)) * load
        return cap - ops.positive_part(cap - local)

    # --- the coefficients of the fluidity equation ---------------------------------------
    def root_pressure(self, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """sqrt(P / rho_s), regularised like mu(I)'s: sqrt(P / rho_s + (eps d)^2)."""
        return ops.sqrt(ops.positive_part(pressure) / self.grain_density
                        + (self.eps * self.grain_diameter) ** 2)

    def inertial_number(self, shear_rate: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """I = gamma_dot d / sqrt(P / rho_s)."""
        return shear_rate * self.grain_diameter / self.root_pressure(pressure, ops)

    def time_scale(self, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """t0: the inertial time d / sqrt(P / rho_s), or the constant of ``time``."""
        if self.time == INERTIAL:
            return self.grain_diameter / self.root_pressure(pressure, ops)
        return float(self.time)

    # --- closed forms --------------------------------------------------------------------
    def local_friction(self, inertial_number: Any) -> Any:
        """mu = mu_s + b I, the homogeneous steady state."""
        return self.mu_s + self.b * inertial_number

    def local_inertial_number(self, mu: float) -> float:
        """The I of the homogeneous steady state at stress ratio mu > mu_s."""
        if mu <= self.mu_s:
            raise ValueError(f"mu = {mu}: the homogeneous state flows only above "
                             f"mu_s = {self.mu_s}")
        return (mu - self.mu_s) / self.b

    def local_fluidity(self, mu: float, pressure: Any) -> Any:
        """g = gamma_dot / mu of the homogeneous steady state at stress ratio mu (0 where
        mu <= mu_s): sqrt(P / rho_s) (mu - mu_s) / (b mu d)."""
        if mu <= self.mu_s:
            return 0.0 * pressure
        return (self.root_pressure(pressure) * (mu - self.mu_s)
                / (self.b * mu * self.grain_diameter))

    def stopping_height(self, slope_deg: float) -> float:
        """h_stop = (pi / 2) A d / sqrt(tan(theta) - mu_s): the thinnest layer in which the
        rest state is unstable (rough base, free surface); infinite at or below mu_s."""
        excess = math.tan(math.radians(slope_deg)) - self.mu_s
        if excess <= 0:
            return math.inf
        return 0.5 * math.pi * self.amplitude * self.grain_diameter / math.sqrt(excess)


def _nonlocal_checks(material: Any, section: str, eps: float) -> Iterator[str]:
    """A positive static friction (the rest state's fluidity is sqrt(2) eps / mu_s), no
    hysteretic friction beside the fluidity, grains at least as dense as the bulk."""
    if material.friction_angle_deg <= 0:
        yield (f"{section}.friction_angle_deg = {material.friction_angle_deg!r} must be > 0 "
               "with rheology = 'nonlocal' (mu_s > 0 sets the fluidity of material at rest)")
    if material.friction == "hysteretic":
        yield (f"{section}.friction = 'hysteretic' cannot be combined with rheology = "
               "'nonlocal': the fluidity already makes layers thinner than h_stop stop; "
               "use friction = 'constant'")
    yield from packing_checks(material, section)


def _build(m: Any, eps: float, fields: LawFields) -> NonlocalFluidity:
    return NonlocalFluidity(viscosity=m.viscosity, friction_angle_deg=m.friction_angle_deg,
                            b=m.nonlocal_b, amplitude=m.nonlocal_amplitude,
                            grain_diameter=m.grain_diameter, grain_density=m.grain_density,
                            eps=eps, time=m.fluidity_time, fluidity=fields.fluidity,
                            friction_cap_deg=m.mu_2_deg)


KEYS = {
    "nonlocal_amplitude": Key(0.48, "nonlocal: A, the cooperative length is A d; 0 = the local "
                                    "law mu = mu_s + b I (Henann & Kamrin 2013, glass beads)",
                              low=0, high=100),
    "nonlocal_b": Key(0.9377, "nonlocal: b of the local law mu = mu_s + b I; glass beads: "
                              "(mu_2 - mu_s) / I0 of Jop et al. (Henann & Kamrin 2013)",
                      low=1e-3, high=100,
                      floor="mu_s + b I would rise by less than 1e-3 up to I = 1: a "
                            "rate-independent law, which the fluidity's equation cannot "
                            "relax (glass beads: 0.9377)"),
    "fluidity_time": Key(INERTIAL, 'nonlocal: t0 of the fluidity\'s relaxation, "inertial" = '
                                   "the local d sqrt(rho_s / p), or a constant (s); no steady "
                                   "state and no stopping height depends on it",
                         low=1e-9, high=1e4, choices=(INERTIAL,)),
}

NONLOCAL = register_rheology(Law(
    "nonlocal", KEYS, _build, _nonlocal_checks,
    reads=("grain_diameter", "grain_density", "mu_2_deg"), one_field=True,
    settings=("numerics.fluidity_coupling", "initial.fluidity", "boundary.bed_fluidity"),
    words="the nonlocal law"))
