"""Material presets: every constant of a named material, for whichever law it runs with.

``material.preset = "glass-beads"`` (or ``layer.preset``) sets the keys below from their
sources; a key the user sets explicitly wins (``config/presets.py`` merges them). Only the
friction angle depends on the law: the constant friction that the paper fits to the
collapses, the static friction mu_s of the beads' mu(I) (which the nonlocal law's b and A
were calibrated with), or, with a hysteretic friction, the repose angle at which flowing
beads stop beside the avalanche angle at which they start.

The glass beads:

- bulk density 1550 kg/m^3 and the constant friction 25.5 deg of Lusso et al., "Two-dimensional
  simulation by regularization of free surface viscoplastic flows with Drucker-Prager yield
  stress and application to granular collapse" (HAL hal-01133786), section 5; grains of
  2500 kg/m^3 (packing fraction 0.62);
- repose 23.5 deg and avalanche 25.5 deg (Mangeney et al. 2010, J. Geophys. Res. 115, F03040;
  Farin, Mangeney & Roche 2014, J. Geophys. Res. Earth Surf. 119);
- mu(I) of Jop, Forterre & Pouliquen (2005, J. Fluid Mech. 541, 167; 2006, Nature 441, 727):
  mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg, I0 = 0.279, for beads of d = 0.53 mm (those of
  Forterre & Pouliquen 2003, whose stopping height ``reference/beads.py`` holds);
- nonlocal fluidity of Henann & Kamrin (2013, PNAS 110, 6730): A = 0.48 and
  b = (mu_2 - mu_s) / I0 = 0.9377 of the same mu(I); the nonlocal law also holds material
  at rest up to mu_2 (``nonlocal_fluidity.py``).

The viscosity beside a friction law is not a property of the beads and is left as it is
(the paper's 1 Pa s by default).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Preset:
    """A material's constants: ``shared`` for every law, the friction angle by law
    (``angle_by_rheology``, and ``angle_hysteretic`` for a Drucker-Prager flow law wrapped by a
    hysteretic friction, whose start angle is among ``shared``); ``fitted_with_angle``: the
    keys of a law fitted together with its friction angle (they mean something else beside
    another angle)."""

    name: str
    shared: dict[str, float]
    angle_by_rheology: dict[str, float]
    angle_hysteretic: float
    fitted_with_angle: dict[str, tuple[str, ...]]

    def values(self, rheology: str, friction: str) -> dict[str, Any]:
        """Every key the preset sets for a material of this rheology and friction (a law
        it has no friction angle for keeps its own)."""
        angle = (self.angle_hysteretic
                 if friction == "hysteretic" and rheology == "drucker-prager"
                 else self.angle_by_rheology.get(rheology))
        return {**self.shared, **({} if angle is None else {"friction_angle_deg": angle})}

    def keys(self) -> tuple[str, ...]:
        return (*self.shared, "friction_angle_deg")


THETA_S_DEG = 20.9          # mu_s of the beads' mu(I)
THETA_2_DEG = 32.76         # mu_2
I0 = 0.279


def _tan(deg: float) -> float:
    return math.tan(math.radians(deg))


GLASS_BEADS = Preset(
    name="glass-beads",
    shared={
        "density": 1550.0,                     # the paper's rho
        "grain_density": 2500.0,
        "grain_diameter": 0.53e-3,             # m, Jop et al.'s beads
        "mu_2_deg": THETA_2_DEG,
        "i0": I0,
        "nonlocal_amplitude": 0.48,
        "nonlocal_b": round((_tan(THETA_2_DEG) - _tan(THETA_S_DEG)) / I0, 4),   # 0.9377
        "start_friction_angle_deg": 25.5,      # the avalanche angle
    },
    angle_by_rheology={"drucker-prager": 25.5, "mu-i": THETA_S_DEG, "nonlocal": THETA_S_DEG},
    angle_hysteretic=23.5,                     # the repose angle
    fitted_with_angle={"mu-i": ("mu_2_deg", "i0"),
                       "nonlocal": ("nonlocal_amplitude", "nonlocal_b")},
)

PRESETS: dict[str, Preset] = {GLASS_BEADS.name: GLASS_BEADS}
