"""Critical-state dilatancy: a packing fraction phi that the flow carries and that relaxes
to the packing of steady flow (Roux & Radjai 1998, "Texture-dependent rigid plastic
behaviour", Physics of Dry Granular Media 350, 229; Pailha & Pouliquen 2009, J. Fluid Mech.
633, 115; Bouchut, Fernandez-Nieto, Mangeney & Narbona-Reina 2016, J. Fluid Mech. 801, 166).

Material denser than the packing of steady flow dilates as it is sheared, looser material
contracts, and the friction carries the difference:

    phi_eq(I) = max(phi_c - a I, phi_min)      the packing of steady flow at I
    tan(psi) = K (phi - phi_eq(I))             the dilatancy angle
    mu = mu_law + tan(psi)                     the friction, with any flow law's
    div u = gamma_dot tan(psi)                 the continuity (in place of div u = 0)
    D phi / Dt = - phi div u                   the mass of the grains

with gamma_dot = sqrt(2) |Du| (|u'| in simple shear, the paper's Frobenius norm, as mu(I)
reads it, ``physics/mu_i.py``) and I = gamma_dot d / sqrt(P / rho_s) the inertial number of
mu(I), P = [p]_+ (for every flow law, Drucker-Prager included). phi_eq = phi_c - a I is the
dense inertial regime (GDR MiDi 2004; da Cruz et al. 2005, Phys. Rev. E 72, 021309);
phi_min is the loosest packing of that regime, where the free surface's I, which grows
without bound as P vanishes, leaves it. In simple shear at a constant I the packing
follows d phi / d gamma = - phi K (phi - phi_eq): its relaxation over a strain of order
1 / (K phi), dense material's friction peak and loose material's dip of K (phi_0 - phi_eq).
The bulk density is rho_s phi (in gravity and inertia). A material's initial packing phi_0
is its ``density / grain_density``; the field the flow carries is the departure from it,
phi - phi_0 (0 at t = 0 in both materials of a column over a layer, whose interface the
layer's tracking carries), so that rho = density + grain_density (phi - phi_0) is the
material's density itself, to the last digit, where the packing has not changed.

In the stress the law's (2.13) factor m of sigma' = m Du gains sqrt(2) tan(psi) P /
sqrt(|Du|^2 + eps^2), the yield stress of the friction tan(psi); the total friction is
kept at least 0 (m >= 2 eta: a packing so loose that tan(psi) < -mu_law carries no shear
by friction, it does not push). The stress keeps the paper's form m Du, whose trace is then
m div u: an isotropic part of order mu p tan(psi) beside the pressure. A bed whose friction
is the material's own law (``boundary.bed = "material"``, ``physics/bed.py``) has it too:
mu_law(I_b) + K (phi - phi_eq(I_b)) at the bed's inertial number I_b, phi at the bed.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from granflow.physics.laws import Key, Law, LawFields, register_packing
from granflow.physics.ops import NUMPY_OPS, Ops

DENSEST = math.pi / (3.0 * math.sqrt(2.0))   # 0.7405: equal spheres' densest packing (Kepler)


@dataclass(frozen=True)
class CriticalState:
    """The packing law of one material (module docstring): ``critical`` phi_c, ``slope``
    a, ``dilatancy`` K, ``loosest`` phi_min, the initial packing phi_0, the grains'
    diameter d (m) and density rho_s (kg/m^3), and eps (1/s), the regularisation of (2.13)
    that mu(I) also uses."""

    critical: float
    slope: float
    dilatancy: float
    loosest: float
    initial: float
    grain_diameter: float
    grain_density: float
    eps: float

    def shear_rate(self, strain_rate_sq: Any, ops: Ops = NUMPY_OPS) -> Any:
        """gamma_dot = sqrt(2) sqrt(|Du|^2 + eps^2), regularised as mu(I)'s."""
        return math.sqrt(2.0) * ops.sqrt(strain_rate_sq + self.eps**2)

    def inertial_number(self, strain_rate_sq: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """I = gamma_dot d / sqrt(P / rho_s + (eps d)^2), as mu(I) has it."""
        root = ops.sqrt(ops.positive_part(pressure) / self.grain_density
                        + (self.eps * self.grain_diameter) ** 2)
        return self.shear_rate(strain_rate_sq, ops) * self.grain_diameter / root

    def equilibrium(self, inertial_number: Any, ops: Ops = NUMPY_OPS) -> Any:
        """phi_eq(I) = max(phi_c - a I, phi_min)."""
        return self.loosest + ops.positive_part(
            self.critical - self.loosest - self.slope * inertial_number)

    def tan_psi(self, packing: Any, strain_rate_sq: Any, pressure: Any,
                ops: Ops = NUMPY_OPS) -> Any:
        """tan(psi) = K (phi - phi_eq(I))."""
        return self.dilatancy * (packing - self.equilibrium(
            self.inertial_number(strain_rate_sq, pressure, ops), ops))

    def volumetric_rate(self, packing: Any, strain_rate_sq: Any, pressure: Any,
                        ops: Ops = NUMPY_OPS) -> Any:
        """div u = gamma_dot tan(psi) (1/s)."""
        return self.shear_rate(strain_rate_sq, ops) * self.tan_psi(packing, strain_rate_sq,
                                                                  pressure, ops)

    def relaxed(self, packing: Any, shear_rate: Any, equilibrium: Any, dt: float) -> Any:
        """phi after dt of D phi / Dt = - gamma_dot K phi (phi - phi_eq) at a constant
        gamma_dot and phi_eq, solved exactly (1 / phi relaxes linearly):
        1 / phi(t) = E / phi_0 + (1 - E) / phi_eq, E = exp(-K gamma_dot phi_eq t).
        It stays between phi_0 and phi_eq; with K = 0 it is phi_0 to the last digit."""
        decay = np.exp(-self.dilatancy * np.asarray(shear_rate) * np.asarray(equilibrium) * dt)
        return np.asarray(packing) / (decay + np.asarray(packing) / equilibrium * (1.0 - decay))


@dataclass(frozen=True)
class Dilatant:
    """The ``Rheology`` of a law ``inner`` with the friction tan(psi) of the packing
    phi = phi_0 + ``departure`` added (a number, an array or a finite-element field: phi -
    phi_0 per triangle; module docstring)."""

    inner: Any
    state: CriticalState
    departure: Any = 0.0

    @property
    def packing(self) -> Any:
        """phi = phi_0 + departure."""
        return self.state.initial + self.departure

    @property
    def viscosity(self) -> Any:
        return self.inner.viscosity

    @property
    def eps(self) -> float:
        return self.state.eps

    @property
    def mu_s(self) -> float:
        """The inner law's static friction (at the critical packing)."""
        return self.inner.mu_s     # type: ignore[no-any-return]

    def with_fields(self, read: Callable[[Any], Any]) -> Dilatant:
        """The law with its per-triangle fields (phi, and the inner law's) passed through
        ``read`` (on a wall: the adjacent triangle's); numbers are left as they are."""
        inner = getattr(self.inner, "with_fields", None)
        departure = (self.departure if isinstance(self.departure, int | float)
                     else read(self.departure))
        return replace(self, inner=self.inner if inner is None else inner(read),
                       departure=departure)

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        """``m`` of the inner law plus sqrt(2) tan(psi) [p]_+ / sqrt(|Du|^2 + eps^2), at
        least 2 eta (a friction of at least 0)."""
        tan_psi = self.state.tan_psi(self.packing, strain_rate_sq, pressure, ops)
        total = self.inner.effective_viscosity_sq(strain_rate_sq, pressure, ops) + (
            math.sqrt(2.0) * tan_psi * ops.positive_part(pressure)
            / ops.sqrt(strain_rate_sq + self.eps**2))
        return ops.maximum(total, 2.0 * self.viscosity)

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)

    def sliding_stress_added(self, slip_speed: Any, load: Any, ops: Ops = NUMPY_OPS) -> Any:
        """tan(psi) [load]_+ sliding at ``slip_speed`` over a bed of its own grains
        (``physics/bed.py``): K (phi - phi_eq(I_b)) at I_b = slip / sqrt(P / rho_s), the
        inertial number of the bed's shear |u_T| / d over a grain, regularised as mu(I)'s;
        phi the packing where the law is read (on the bed: the triangle on it)."""
        state, load = self.state, ops.positive_part(load)
        root = ops.sqrt(load / state.grain_density + (state.eps * state.grain_diameter) ** 2)
        equilibrium = state.equilibrium(slip_speed / root, ops)
        return state.dilatancy * (self.packing - equilibrium) * load

    def yield_slope_extra(self, strain_rate_sq: np.ndarray,
                          pressure: np.ndarray) -> np.ndarray:
        """sqrt(2) tan(psi), the yield stress per unit of [p]_+ this law adds, at points
        given three per triangle (the primal-dual correction's, ``fem/primal_dual.py``)."""
        departure = self.departure
        if not isinstance(departure, int | float):
            departure = np.repeat(departure.vec.FV().NumPy(), 3)
        return math.sqrt(2.0) * np.asarray(self.state.tan_psi(
            self.state.initial + departure, strain_rate_sq, pressure))


def initial_packing(material: Any) -> float:
    """phi at t = 0: the material's density over its grains' (module docstring)."""
    return float(material.density / material.grain_density)


def critical_state(material: Any, eps: float) -> CriticalState:
    """A material's packing law from its keys."""
    return CriticalState(critical=material.packing_critical, slope=material.packing_slope,
                         dilatancy=material.packing_dilatancy,
                         loosest=material.packing_loosest, initial=initial_packing(material),
                         grain_diameter=material.grain_diameter,
                         grain_density=material.grain_density, eps=eps)


def bulk_density(material: Any, fields: LawFields) -> Any:
    """rho_s phi = density + grain_density (phi - phi_0), ``fields.packing`` the departure
    phi - phi_0 (module docstring)."""
    if fields.packing is None:
        return material.density
    return material.density + material.grain_density * fields.packing


def _build(material: Any, eps: float, fields: LawFields, flow: Any) -> Dilatant:
    departure = 0.0 if fields.packing is None else fields.packing
    return Dilatant(flow, critical_state(material, eps), departure)


def _checks(material: Any, section: str, eps: float) -> Iterator[str]:
    """An initial packing a sphere packing can have; phi_min below phi_c."""
    start = initial_packing(material)
    if start > DENSEST:
        yield (f"{section}.density / {section}.grain_density = {start:.4g} is the initial "
               f"packing fraction with packing = 'critical-state' and must be at most "
               f"{DENSEST:.4f}, the densest packing of equal spheres; lower the density or "
               "raise the grain density")
    if material.packing_loosest >= material.packing_critical:
        yield (f"{section}.packing_loosest = {material.packing_loosest!r} must be below "
               f"{section}.packing_critical = {material.packing_critical!r} (the packing of "
               "steady flow falls from phi_c with I down to phi_min)")


KEYS = {
    "packing_critical": Key(
        0.60, "critical-state: phi_c, the packing of steady flow as I -> 0; glass beads: "
              "between a poured bed (~0.58) and a vibrated one (~0.62)", low=0.3,
        high=round(DENSEST, 4)),
    "packing_slope": Key(
        0.0, "critical-state: a of phi_eq(I) = phi_c - a I, the dense inertial regime "
             "(GDR MiDi 2004; da Cruz et al. 2005: 0.1-0.3); 0 = phi_c at every I (a > 0 "
             "can stall the iteration near the free surface, docs/model.md)", low=0, high=10),
    "packing_dilatancy": Key(
        4.0, "critical-state: K of tan(psi) = K (phi - phi_eq), the friction per unit of "
             "packing (Pailha & Pouliquen 2009); 0 = no dilatancy (incompressible)",
        low=0, high=100),
    "packing_loosest": Key(
        0.5, "critical-state: phi_min, the loosest packing of steady dense flow, where "
             "phi_eq stops falling with I (at I = 0.5 with a = 0.2)", low=0.1,
        high=round(DENSEST, 4)),
}

CRITICAL_STATE = register_packing(Law(
    "critical-state", KEYS, _build, _checks, reads=("grain_diameter", "grain_density"),
    one_field=True, density=bulk_density,
    words="the critical-state packing"))
