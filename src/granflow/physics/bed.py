"""What the rigid bed exerts on the material sliding over it: the laws of ``boundary.bed``
besides the paper's regularised Coulomb friction (2.17a) (``friction.py``).

Each gives, like ``CoulombFriction``, the factor c of the tangential traction -c u_T from
the slip speed squared and the normal load [p - sigma'_N]_+ (``drag_coefficient_sq``):

- ``NoSlip``: u_T = 0, imposed by a penalty, c = xi: the traction is whatever holds the
  material (a rough bed that does not slide);
- ``MaterialBed``: the material's own law at the bed's slip rate. The bed of the
  experiments is glued beads of the flowing beads' size: the first layer of free grains
  slides over the glued one, a shear of one grain diameter, at the rate |u_T| / d. The
  bed's traction is the material's friction at that rate, without the regularising
  viscosity (the bed is not the continuum the viscosity stands in for):

      tau_b = mu(I_b) P,   I_b = (|u_T| / d) d / sqrt(P / rho_s) = |u_T| / sqrt(P / rho_s),

  independent of d. For a rate-independent law mu(I) = mu_s, so Drucker-Prager at 25.5
  degrees over this bed is the paper's Coulomb bed at 25.5 degrees; for mu(I) the bed
  holds at mu_s (weaker than 25.5 degrees for the glass beads' tan 20.9) and resists up to
  mu_2 where the slip is fast; for the nonlocal law the bed has its local law mu_s + b I_b
  (capped at mu_2 as the law is, ``nonlocal_fluidity.py``); a hysteretic friction blends
  mu_start and the flowing law with the state of the material at the bed. A steady
  layer over it is the same layer over a no-slip bed with the velocity shifted by the
  slip d gamma_dot(0): its basal shear rate continued one grain into the bed. With a
  packing fraction the material's friction is mu(I) + tan(psi) (``packing.py``), and so is
  the bed's: tau_b = (mu(I_b) + K (phi - phi_eq(I_b))) P, phi the packing of the material
  at the bed (the triangle on it), at least 0.

Each simple law gives the stress it exerts sliding (``sliding_stress(slip, load, ops)``,
finite at zero load); ``physics/composite.py`` blends those of a composite law.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from granflow.physics.composite import blended
from granflow.physics.ops import NUMPY_OPS, Ops


@dataclass(frozen=True)
class NoSlip:
    """u_T = 0 on the bed by the penalty ``penalty`` (the normal penalty's xi): c = xi."""

    penalty: float
    reads_load = False       # the traction does not depend on the normal load

    def __post_init__(self) -> None:
        if self.penalty <= 0:
            raise ValueError(f"penalty = {self.penalty}: must be > 0")

    def drag_coefficient_sq(self, slip_sq: Any, normal_stress: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        return self.penalty + 0.0 * slip_sq


@dataclass(frozen=True)
class MaterialBed:
    """The bed's traction -tau_b u_T / |u_T|, tau_b the stress ``law`` exerts sliding at
    |u_T| over a bed of its own grains (module docstring); |u_T| regularised by
    ``eps_friction`` (m/s) as in (2.17a). ``law`` is the run's law (a composite one is
    blended: a hysteretic friction's state, a layer's material, as the wall reads them)."""

    law: Any
    eps_friction: float

    def __post_init__(self) -> None:
        if self.eps_friction <= 0:
            raise ValueError(f"eps_friction = {self.eps_friction}: must be > 0")

    def traction(self, slip_speed: Any, normal_stress: Any, ops: Ops = NUMPY_OPS) -> Any:
        """tau_b at the slip speed ``slip_speed`` (m/s) and the normal load; a law wrapping
        another adds its own friction sliding (a packing's tan(psi) at the bed), the total
        kept at least 0 (as in the material: the bed holds back, it never pushes)."""
        return ops.positive_part(blended(
            self.law, lambda law: law.sliding_stress(slip_speed, normal_stress, ops),
            added=lambda wrapper: wrapper.sliding_stress_added(slip_speed, normal_stress,
                                                               ops)))

    def drag_coefficient_sq(self, slip_sq: Any, normal_stress: Any,
                            ops: Ops = NUMPY_OPS) -> Any:
        """c with traction = -c u_T: tau_b(|u_T|_eps) / |u_T|_eps, |u_T|_eps =
        sqrt(|u_T|^2 + eps_f^2)."""
        slip = ops.sqrt(slip_sq + self.eps_friction**2)
        return self.traction(slip, normal_stress, ops) / slip
