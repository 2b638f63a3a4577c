"""Steady flow down an incline steeper than the friction: the 2D periodic layer against the
exact profiles of reference/incline.py. Coarse: 8 cells across the 1 cm layer,
dt = 5e-3 s, to t = 6 s (steady to < 1e-3); the finer study is benchmarks/incline.py."""

import dataclasses
import math

import numpy as np
import pytest

from granflow.config import load_config
from granflow.physics import MuI
from granflow.reference.incline import bagnold_profile
from granflow.scenarios.materials import build_rheology
from granflow.scenarios.plug_flow import build_plug_flow

COARSE = ["mesh.size=0.00125", "time.dt=5e-3", "time.t_end=6.0", "time.output_times=[]"]


def run_layer(overrides: list[str]):
    problem = build_plug_flow(load_config("incline-mu-i", COARSE + overrides))
    problem.simulation.run()
    return problem


@pytest.mark.parametrize("slope", [23.0, 27.0])
def test_mu_i_layer_reaches_bagnold_profile(slope: float) -> None:
    """Within 1 % (relative L2) of the exact steady mu(I) profile and of Bagnold's closed
    form (eta = 0; the scenario's eta = 1e-4 Pa s moves it by ~1e-3)."""
    problem = run_layer([f"geometry.slope_deg={slope}"])
    error = problem.velocity_error(problem.simulation.t)
    assert problem.reference_kind == "steady"
    assert error < 0.01, error
    law = build_rheology(problem.config)
    assert isinstance(law, MuI)
    bagnold = bagnold_profile(height=0.01, slope_deg=slope,
                              law=dataclasses.replace(law, viscosity=0.0), density=1500.0)
    z, u, _ = problem.profile(problem.simulation.t)
    ref = bagnold(z)
    l2 = math.sqrt(np.trapezoid((u[:, 0] - ref) ** 2, z) / np.trapezoid(ref**2, z))
    assert l2 < 0.01, l2
    assert error > 1e-7                    # a real discretisation error, not a copy


def test_drucker_prager_layer_reaches_parabola() -> None:
    problem = run_layer(["geometry.slope_deg=25", "material.rheology=drucker-prager",
                         "material.viscosity=0.5"])
    assert problem.reference_kind == "steady"
    assert problem.velocity_error(problem.simulation.t) < 0.01


def test_mu_i_below_friction_has_no_reference() -> None:
    problem = build_plug_flow(load_config("incline-mu-i", COARSE + [
        "geometry.slope_deg=15", "time.t_end=0.01"]))
    assert problem.reference_kind is None
    assert "comes to rest" in (problem.reference_note() or "")
