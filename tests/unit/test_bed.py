"""The rigid bed's laws (``physics/bed.py``): the material bed is each law's friction at the
slip's inertial number I_b = |u_T| / sqrt(P / rho_s); Drucker-Prager's is its Coulomb bed;
with a packing fraction it adds the dilatancy K (phi - phi_eq(I_b))."""

from __future__ import annotations

import math

import numpy as np
import pytest

from granflow.physics import CoulombFriction, DruckerPrager, Hysteretic, MuI, NonlocalFluidity
from granflow.physics.bed import MaterialBed, NoSlip
from granflow.physics.hysteresis import Relaxation
from granflow.physics.packing import CriticalState, Dilatant
from granflow.physics.regions import TwoMaterials

SLIP = np.array([0.0, 1e-4, 0.01, 0.3, 2.0])
LOAD = np.array([0.0, 10.0, 150.0, 150.0, 2000.0])
EPS_F = 1e-6
BEADS = MuI(viscosity=1.0, friction_angle_deg=20.9, mu_2_deg=32.76, i0=0.279,
            grain_diameter=0.00053, grain_density=2500.0, eps=1e-6)


def test_drucker_pragers_material_bed_is_its_coulomb_bed_to_round_off() -> None:
    law = DruckerPrager(viscosity=1.0, friction_angle_deg=25.5, eps=1e-6)
    material = MaterialBed(law, EPS_F).drag_coefficient_sq(SLIP**2, LOAD)
    coulomb = CoulombFriction(25.5, EPS_F).drag_coefficient_sq(SLIP**2, LOAD)
    np.testing.assert_allclose(material, coulomb, rtol=1e-15)


def test_mu_i_bed_is_mu_of_the_slips_inertial_number() -> None:
    """tau_b / P = mu(I_b), I_b = slip / sqrt(P / rho_s): mu_s at rest, mu_2 fast."""
    slip, load = np.array([1e-3, 0.05, 0.5, 50.0]), np.array([150.0, 150.0, 400.0, 100.0])
    tau = MaterialBed(BEADS, EPS_F).traction(slip, load)
    inertial = slip / np.sqrt(load / 2500.0)
    np.testing.assert_allclose(tau / load, BEADS.friction(inertial), rtol=1e-6)
    assert tau[0] / load[0] == pytest.approx(BEADS.mu_s, rel=1e-2)
    assert tau[-1] / load[-1] == pytest.approx(BEADS.mu_2, rel=1e-2)
    assert MaterialBed(BEADS, EPS_F).traction(np.array([0.3]), np.array([0.0]))[0] == 0.0


def test_nonlocal_bed_is_its_local_law_capped_at_mu_2() -> None:
    law = NonlocalFluidity(viscosity=1.0, friction_angle_deg=20.9, b=0.9377, amplitude=0.48,
                           grain_diameter=0.00053, grain_density=2500.0, eps=1e-6,
                           friction_cap_deg=32.76)
    load = np.full(3, 150.0)
    slip = np.array([1e-3, 0.02, 1.0])
    tau = MaterialBed(law, EPS_F).traction(slip, load)
    local = law.local_friction(slip / np.sqrt(load / 2500.0))
    np.testing.assert_allclose(tau / load, np.minimum(local, math.tan(math.radians(32.76))),
                               rtol=1e-6)
    assert local[-1] > math.tan(math.radians(32.76))      # the cap acts on the fast one


def test_composite_laws_blend_their_parts_beds() -> None:
    """A hysteretic friction with the state s of the material at the bed; a layer's share."""
    start = DruckerPrager(viscosity=1.0, friction_angle_deg=25.5, eps=1e-6)
    s = np.array([0.0, 0.5, 1.0])
    hysteretic = Hysteretic(flow=BEADS, start=start, relaxation=Relaxation(0.02, 0.02, 1.0),
                            mobilisation=s)
    slip, load = np.full(3, 0.05), np.full(3, 150.0)
    tau = MaterialBed(hysteretic, EPS_F).traction(slip, load)
    flowing = BEADS.sliding_stress(slip, load)
    np.testing.assert_allclose(tau, (1 - s) * start.mu_s * load + s * flowing)
    two = TwoMaterials(start, BEADS, s, None)
    np.testing.assert_allclose(MaterialBed(two, EPS_F).traction(slip, load), tau)


def test_no_slip_is_the_penalty_whatever_the_load() -> None:
    drag = NoSlip(1e12).drag_coefficient_sq(SLIP**2, LOAD)
    np.testing.assert_array_equal(drag, np.full(len(SLIP), 1e12))
    with pytest.raises(ValueError, match="penalty"):
        NoSlip(0.0)


def test_a_packings_bed_adds_the_dilatancy_at_the_beds_inertial_number() -> None:
    """Glass beads' mu(I) with a packing: tau_b / P = mu(I_b) + K (phi - phi_eq(I_b)),
    phi_eq = max(phi_c - a I_b, phi_min), both written out here from their definitions; a
    dense packing raises the bed's friction, a loose one lowers it, and one so loose that
    the sum is negative gives no traction (the bed does not push)."""
    state = CriticalState(critical=0.60, slope=0.2, dilatancy=4.0, loosest=0.5, initial=0.58,
                          grain_diameter=0.00053, grain_density=2500.0, eps=1e-6)
    departure = np.array([0.04, -0.04, 0.02, -0.03, -0.08])      # phi - phi_0, per point
    slip = np.array([0.05, 0.05, 0.5, 0.2, 1e-3])
    load = np.array([150.0, 150.0, 400.0, 100.0, 150.0])
    tau = MaterialBed(Dilatant(BEADS, state, departure), EPS_F).traction(slip, load)
    inertial = slip / np.sqrt(load / 2500.0)
    mu_s, mu_2 = math.tan(math.radians(20.9)), math.tan(math.radians(32.76))
    mu = mu_s + (mu_2 - mu_s) * inertial / (0.279 + inertial)
    tan_psi = 4.0 * (0.58 + departure - np.maximum(0.60 - 0.2 * inertial, 0.5))
    np.testing.assert_allclose(tau / load, np.maximum(mu + tan_psi, 0.0), rtol=1e-6)
    assert tau[0] > BEADS.sliding_stress(slip, load)[0] > tau[1]   # dense > beads > loose
    assert tau[-1] == 0.0 and (mu + tan_psi)[-1] < 0               # not a push


def test_drucker_pragers_bed_with_a_packing_is_a_coulomb_bed_at_mu_plus_tan_psi() -> None:
    """With a = 0 (phi_eq = phi_c): Drucker-Prager's material bed at a uniform phi is the
    Coulomb bed at the angle whose tangent is tan(25.5 deg) + K (phi - phi_c)."""
    law = DruckerPrager(viscosity=1.0, friction_angle_deg=25.5, eps=1e-6)
    for phi in (0.62, 0.58):
        state = CriticalState(critical=0.60, slope=0.0, dilatancy=4.0, loosest=0.5,
                              initial=phi, grain_diameter=5e-4, grain_density=2500.0,
                              eps=1e-6)
        material = MaterialBed(Dilatant(law, state), EPS_F).drag_coefficient_sq(SLIP**2, LOAD)
        angle = math.degrees(math.atan(math.tan(math.radians(25.5)) + 4.0 * (phi - 0.60)))
        coulomb = CoulombFriction(angle, EPS_F).drag_coefficient_sq(SLIP**2, LOAD)
        np.testing.assert_allclose(material, coulomb, rtol=1e-12)
