"""Hysteretic friction: material that needs more friction to start than it keeps while it
flows (the h_start / h_stop picture of Pouliquen & Forterre 2002, J. Fluid Mech. 453;
the friction laws of Edwards et al. 2017, J. Fluid Mech. 823, and 2019, J. Fluid Mech. 875).

A mobilisation state s in [0, 1], carried with the material, sets the friction of the
yield stress of (2.13):

    mu = (1 - s) mu_start + s mu_flow,     kappa = sqrt(2) mu [p]_+,

with mu_flow = tan(friction angle), or mu(I) (``physics/mu_i.py``). Along the material's
path s relaxes towards 1 where the material is sheared and towards 0 where it is not:

    Ds/Dt = (s_target - s) / tau,   s_target = 1, tau = tau_m   if gamma_dot > gamma_c,
                                    s_target = 0, tau = tau_r   otherwise,

gamma_dot = sqrt(2) |Du| (|u'| in simple shear). The threshold gamma_c sits far above the
creep of the regularised law (rates of order eps where |sigma'| < kappa), so material held
by its friction stays at rest. Over a step of length dt with the target held, the
relaxation is solved exactly: s <- s_target + (s - s_target) exp(-dt / tau).

Because s has a memory (tau > 0), the friction at any instant is a given field, not a
function of the instantaneous rate: the momentum problem of a step is the law (2.13) with a
friction that varies in space. A friction that drops at once with the rate is rate-weakening,
which makes the incompressible equations ill-posed (Barker & Gray 2017, J. Fluid Mech. 828).

``m`` of sigma' = m Du is linear in kappa and both laws share eta, so the hysteretic law is
the start law (Drucker-Prager at mu_start) and the flow law blended with s, as
``physics/regions.py`` blends two materials; it is evaluated as one law with the blended
yield stress (one regularised rate instead of two in the assembled coefficient).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from granflow.physics.composite import composites
from granflow.physics.laws import Key, Law, LawFields, register_friction
from granflow.physics.mu_i import MuI
from granflow.physics.ops import NUMPY_OPS, Ops
from granflow.physics.regions import blend
from granflow.physics.rheology import DruckerPrager


@dataclass(frozen=True)
class Relaxation:
    """The relaxation of s (module docstring): ``mobilisation_time`` tau_m (s),
    ``rest_time`` tau_r (s) and ``shear_rate`` gamma_c (1/s). Each may be a number or an
    array (one value per cell: a column over a layer of another material)."""

    mobilisation_time: Any
    rest_time: Any
    shear_rate: Any

    def __post_init__(self) -> None:
        for name in ("mobilisation_time", "rest_time", "shear_rate"):
            if np.any(np.asarray(getattr(self, name)) <= 0):
                raise ValueError(f"{name} = {getattr(self, name)}: must be > 0")

    def sheared(self, shear_rate: Any) -> np.ndarray:
        """Where gamma_dot = sqrt(2) |Du| exceeds gamma_c: there s tends to 1."""
        return np.asarray(shear_rate) > self.shear_rate

    def relax(self, s: Any, shear_rate: Any, dt: float) -> np.ndarray:
        """s after dt with the target of ``shear_rate`` held: the exact solution of
        Ds/Dt = (s_target - s) / tau over the step."""
        sheared = self.sheared(shear_rate)
        target = sheared.astype(float)
        tau = np.where(sheared, self.mobilisation_time, self.rest_time)
        with np.errstate(over="ignore", under="ignore"):   # dt >> tau: exp(-inf) = 0
            return target + (np.asarray(s, dtype=float) - target) * np.exp(-dt / tau)


def relaxed(s0: float, target: float, tau: float, t: float) -> float:
    """The ODE's solution s(t) = target + (s0 - target) exp(-t / tau) (for the tests and
    for material that has been at rest since t = 0)."""
    return target + (s0 - target) * math.exp(-t / tau)


def pick(column: Any, layer: Any, fraction: Any) -> Any:
    """Per cell, the column's value where it holds most of the cell, the layer's elsewhere:
    the relaxation of a cell the interface crosses is its main material's."""
    return np.where(np.asarray(fraction) >= 0.5, layer, column)


@dataclass(frozen=True)
class Hysteretic:
    """The ``Rheology`` with mu = (1 - s) mu_start + s mu_flow (module docstring).

    ``flow`` is the law of the flowing material (Drucker-Prager (2.13) or mu(I)); ``start``
    the Drucker-Prager law at the start friction, with the same viscosity and eps;
    ``mobilisation`` is s where the law is evaluated (a number, an array or a finite-element
    coefficient function), ``per_triangle`` its values triangle by triangle (an object with
    the engine's ``vec``, for ``fem/primal_dual.py`` and the outputs)."""

    flow: DruckerPrager | MuI
    start: DruckerPrager
    relaxation: Relaxation
    mobilisation: Any
    per_triangle: Any = None
    initial: float = 0.0       # s of the material at t = 0

    def __post_init__(self) -> None:
        if not 0.0 <= self.initial <= 1.0:
            raise ValueError(f"initial_mobilisation = {self.initial}: must be in [0, 1]")
        if (self.start.viscosity, self.start.eps) != (self.flow.viscosity,
                                                      getattr(self.flow, "eps", None)):
            raise ValueError("the start and flow laws must share the viscosity and eps")

    @property
    def parts(self) -> tuple[DruckerPrager, DruckerPrager | MuI]:
        """At s = 0 the start law, at s = 1 the flow law (``physics/composite.py``)."""
        return self.start, self.flow

    @property
    def share(self) -> Any:
        return self.mobilisation

    @property
    def viscosity(self) -> float:
        return self.flow.viscosity

    @property
    def eps(self) -> float:
        return self.start.eps

    @property
    def mu_start(self) -> float:
        return self.start.mu_s

    def with_fields(self, read: Callable[[Any], Any]) -> Hysteretic:
        """The law with its mobilisation passed through ``read`` (on a wall: the adjacent
        triangle's), a number left as it is."""
        if isinstance(self.mobilisation, int | float):
            return self
        return replace(self, mobilisation=read(self.mobilisation))

    def yield_stress_sq(self, strain_rate_sq: Any, pressure: Any, ops: Ops = NUMPY_OPS) -> Any:
        """kappa = sqrt(2) ((1 - s) mu_start + s mu_flow) [p]_+ (2.4), mu_flow = mu(I) at
        the regularised rate for a mu(I) flow law."""
        s, flow = self.mobilisation, self.flow
        if isinstance(flow, DruckerPrager):     # one friction, one product
            return math.sqrt(2.0) * blend(self.start.mu_s, flow.mu_s, s) * ops.positive_part(
                pressure)
        assert isinstance(flow, MuI)
        return blend(self.start.yield_stress(pressure, ops),
                     flow.yield_stress_sq(strain_rate_sq, pressure, ops), s)

    def effective_viscosity_sq(self, strain_rate_sq: Any, pressure: Any,
                               ops: Ops = NUMPY_OPS) -> Any:
        """``m`` of (2.13): 2 eta + kappa / sqrt(|Du|^2 + eps^2), kappa of both frictions."""
        return 2.0 * self.viscosity + self.yield_stress_sq(strain_rate_sq, pressure, ops) / (
            ops.sqrt(strain_rate_sq + self.eps**2))

    def effective_viscosity(self, strain_rate_norm: Any, pressure: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.effective_viscosity_sq(strain_rate_norm**2, pressure, ops)


def mobilisation_cells(law: Any) -> Any:
    """The per-triangle mobilisation a law reads (the engine's object), or None when no
    material of ``law`` (one law, or a column over a layer) has a hysteretic friction."""
    return next((c.per_triangle for c in composites(law) if isinstance(c, Hysteretic)), None)


def relaxation(material: Any) -> Relaxation:
    """The relaxation of a material's mobilisation (its hysteretic-friction keys)."""
    return Relaxation(mobilisation_time=material.mobilisation_time,
                      rest_time=material.rest_time, shear_rate=material.mobilisation_shear_rate)


def _hysteretic(m: Any, eps: float, fields: LawFields, flow: Any) -> Hysteretic:
    """The material's law as mu_flow beside Drucker-Prager at mu_start, blended with s."""
    start = DruckerPrager(viscosity=m.viscosity, friction_angle_deg=m.start_friction_angle_deg,
                          eps=eps)
    return Hysteretic(flow=flow, start=start, relaxation=relaxation(m),
                      mobilisation=fields.mobilisation, per_triangle=fields.per_triangle,
                      initial=m.initial_mobilisation)


CREEP_MARGIN = 100.0   # mobilisation_shear_rate / eps at least: the creep of (2.13) at rest,
                       # eps ratio / sqrt(1 - ratio^2), passes it only within 5e-5 of yield


def _checks(material: Any, section: str, eps: float) -> Iterator[str]:
    """The friction at rest at least the flowing one; a threshold far above the
    regularisation's creep."""
    if material.start_friction_angle_deg < material.friction_angle_deg:
        yield (f"{section}.start_friction_angle_deg = {material.start_friction_angle_deg!r} "
               f"must be at least the friction angle {material.friction_angle_deg!r} (the "
               "friction at rest is the larger)")
    if material.mobilisation_shear_rate < CREEP_MARGIN * eps:
        yield (f"{section}.mobilisation_shear_rate = {material.mobilisation_shear_rate!r} must "
               f"be at least {CREEP_MARGIN:g} x numerics.eps = {CREEP_MARGIN * eps:.3g} "
               "(material at rest creeps at rates of order eps and must not count as sheared)")


MICROSECOND = ("a microsecond: a thousandth of the time sqrt(d / g) of grains of 10 "
               "micrometres")
KEYS = {
    "start_friction_angle_deg": Key(
        27.5, "hysteretic: mu_start = tan(angle), the friction at rest; at least "
              "friction_angle_deg. 27.5 = 25.5 + the 2 deg between the glass beads' avalanche "
              "(25.5) and repose (23.5) angles (Mangeney et al. 2010; Farin et al. 2014)",
        low=0, below=90),
    "mobilisation_time": Key(
        0.02, "hysteretic: tau_m (s), the time sheared material takes to reach mu_flow "
              "(s -> 1); 0.02 s ~ 3 sqrt(d/g) for d = 0.5 mm", low=1e-6, high=1e4,
        floor=MICROSECOND),
    "rest_time": Key(
        0.02, "hysteretic: tau_r (s), the time material at rest takes to regain mu_start "
              "(s -> 0); a few sqrt(d/g), d = grain_diameter", low=1e-6, high=1e4,
        floor=MICROSECOND),
    "mobilisation_shear_rate": Key(
        1.0, "hysteretic: material is sheared where sqrt(2) |Du| (|du/dz| in simple shear) "
             "exceeds this (1/s); at least 100 numerics.eps (the regularised law creeps at "
             "rates ~ eps at rest). 1 1/s: in the rectangle's collapse, cells slower than "
             "1 mm/s shear at most at 0.335 1/s, flowing ones at 4-12 1/s "
             "(benchmarks/hysteresis.py)", above=0, high=1e6),
    "initial_mobilisation": Key(0.0, "hysteretic: s at t = 0 (0: at rest, 1: flowing)",
                                low=0, high=1),
}

HYSTERETIC = register_friction(Law("hysteretic", KEYS, _hysteretic, _checks,
                                   words="the hysteretic friction"))
