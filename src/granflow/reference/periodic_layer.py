"""The 1D reference of a periodic layer on an incline, by law: each law that has one has it
attached to its registration here (``physics/laws.py: register_reference``), and the
periodic layer (``scenarios/plug_flow.py``) asks ``layer_reference``, which says in one line
why there is none for a law that registered none (it never uses another law's).

A rheology's reference reads the run's configuration (any object with its sections as
attributes) and gives a ``Reference``, or the line that says why none applies:

- Drucker-Prager (2.13): below its friction angle the transient plug flow of (4.1)
  (``plug1d.py``, paper section 4), steeper the steady profile it tends to (``incline.py``);
- mu(I): the steady profile when mu_s < tan(slope) < mu_2, else none (the layer comes to
  rest, or keeps accelerating);
- the nonlocal law: the steady flow of a layer thicker than its stopping height
  (``nonlocal_incline.py``), else none.

A friction wraps the rheology's reference: a constant one leaves it; a hysteretic one keeps
the steady profile of the flowing law (a layer that keeps flowing is mobilised, mu =
mu_flow) and has no transient (the 1D solver's friction is constant). A packing wraps the
friction's: none leaves it; a packing fraction has none (the 1D solvers are incompressible).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from granflow.physics.laws import LawFields, laws_of, register_reference
from granflow.reference.incline import SteadyProfile, drucker_prager_profile, mu_i_profile
from granflow.reference.nonlocal_incline import steady_nonlocal_flow
from granflow.reference.plug1d import Plug1DSolution, solve_plug1d


@dataclass(frozen=True)
class Reference:
    """A reference of a periodic layer: ``kind`` "1d" (the transient of (4.1)) or "steady"
    (the profile the layer tends to); ``at(t)`` its solution at time t."""

    kind: str
    at: Callable[[float], Plug1DSolution | SteadyProfile]


RheologyReference = Callable[[Any], Reference | str]


def steep(config: Any) -> bool:
    """Slope steeper than the friction angle: no plug, the layer shears throughout."""
    return bool(config.geometry.slope_deg > config.material.friction_angle_deg)


def _law(config: Any) -> Any:
    """The material's flow law (its rheology, without its friction), reading no field."""
    rheology = laws_of(config.material)[0]
    return rheology.build(config.material, config.numerics.eps, LawFields())


def _common(config: Any) -> dict[str, float]:
    return {"height": config.geometry.height, "slope_deg": config.geometry.slope_deg,
            "density": config.material.density, "gravity": config.material.gravity}


def drucker_prager(config: Any) -> Reference | str:
    """Below the friction angle the 1D solution of (4.1), steeper the steady profile."""
    mat = config.material
    if steep(config):
        return Reference("steady", lambda t: drucker_prager_profile(
            friction_angle_deg=mat.friction_angle_deg, viscosity=mat.viscosity,
            **_common(config)))
    return Reference("1d", lambda t: solve_plug1d(
        height=config.geometry.height, slope_deg=config.geometry.slope_deg,
        friction_angle_deg=mat.friction_angle_deg, kinematic_viscosity=mat.viscosity / mat.density,
        shear_rate=config.initial.shear_rate, plug_base=config.initial.plug_base, t_end=t,
        gravity=mat.gravity))


def mu_i(config: Any) -> Reference | str:
    """The steady profile when mu_s < tan(slope) < mu_2."""
    mat, slope = config.material, config.geometry.slope_deg
    if not steep(config):
        return (f"no reference: the 1D solver of (4.1) is for Drucker-Prager, and a mu(I) "
                f"layer at geometry.slope_deg = {slope:g} <= material.friction_angle_deg "
                f"= {mat.friction_angle_deg:g} comes to rest")
    if slope >= mat.mu_2_deg:
        return (f"no reference: geometry.slope_deg = {slope:g} >= material.mu_2_deg = "
                f"{mat.mu_2_deg:g}, the mu(I) layer keeps accelerating")
    return Reference("steady", lambda t: mu_i_profile(law=_law(config), **_common(config)))


def nonlocal_layer(config: Any) -> Reference | str:
    """The steady flow of a layer thicker than its stopping height, steeper than mu_s."""
    law, geo = _law(config), config.geometry
    h_stop = law.stopping_height(geo.slope_deg)
    if law.amplitude > 0 and geo.height <= h_stop:
        return (f"no reference: the nonlocal layer of geometry.height = {geo.height:g} m is "
                f"not thicker than its stopping height {h_stop:.4g} m at geometry.slope_deg "
                f"= {geo.slope_deg:g}: it comes to rest")
    if not steep(config):
        return (f"no reference: geometry.slope_deg = {geo.slope_deg:g} <= "
                f"material.friction_angle_deg = {config.material.friction_angle_deg:g}: the "
                "nonlocal layer comes to rest")
    return Reference("steady", lambda t: steady_nonlocal_flow(law=law, **_common(config)
                                                              ).profile)


def constant_friction(config: Any, flow: RheologyReference) -> Reference | str:
    return flow(config)


def hysteretic_friction(config: Any, flow: RheologyReference) -> Reference | str:
    """The flowing law's steady profile; no transient (the 1D solver's friction is
    constant)."""
    if not steep(config):
        mat = config.material
        return ("no reference: the 1D solver of (4.1) has a constant friction, and "
                f"geometry.slope_deg = {config.geometry.slope_deg:g} <= "
                f"material.friction_angle_deg = {mat.friction_angle_deg:g}")
    return flow(config)


def no_packing(config: Any, flow: RheologyReference) -> Reference | str:
    return flow(config)


def layer_reference(config: Any) -> Reference | str:
    """The reference of a periodic layer of ``config``'s material, or why none applies."""
    mat = config.material
    rheology, friction, packing = laws_of(mat)
    for key, law in (("rheology", rheology), ("friction", friction), ("packing", packing)):
        if law.reference is None:
            return (f"no reference: material.{key} = {getattr(mat, key)!r} registers no 1D "
                    "reference of a periodic layer")
    flow = functools.partial(friction.reference, flow=rheology.reference)
    return packing.reference(config, flow)  # type: ignore[no-any-return]


register_reference("drucker-prager", drucker_prager)
register_reference("mu-i", mu_i)
register_reference("nonlocal", nonlocal_layer)
register_reference("constant", constant_friction)
register_reference("hysteretic", hysteretic_friction)
register_reference("none", no_packing)
