"""The nonlocal fluidity law (physics/nonlocal_fluidity.py) in the 2D solver, on the
periodic incline (rough no-slip base, free surface), glass beads of Henann & Kamrin (2013):
mu_s = tan 20.9 deg, b = 0.9377, A = 0.48, d = 0.5 mm, rho_s = 2500 kg/m^3.

(a) With A = 0 the law is local, mu = mu_s + b I: the layer reaches Bagnold's profile of that
    law (closed form, eta = 0) within 1e-3 (relative L2; 16 cells across a 1 cm layer, eta =
    1e-6 Pa s; measured 4.3e-4, 5.4e-4 at 8 cells; the scenario's 1e-4 Pa s alone moves the
    profile by 8.9e-4).
(b) The rest state g = 0 is unstable exactly in layers thicker than the model's stopping
    height h_stop = (pi / 2) A d / sqrt(tan(theta) - mu_s). The growth rate of a small
    fluidity is measured at 0.9 and 1.1 h_stop (8 cells across, dt = 0.01 s, its log-slope
    over t = 0.4-1 s); it decays below and grows above, and its zero, interpolated linearly
    in 1 / h^2 (the rate of the quarter-wave mode is linear in it), is h_stop within 5 % at
    four angles from 22 to 30 deg. The finer study is benchmarks/nonlocal_incline.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from granflow.config import load_config
from granflow.reference.incline import bagnold
from granflow.scenarios.fluidity import fluidity_growth_rate
from granflow.scenarios.materials import nonlocal_law
from granflow.scenarios.plug_flow import build_plug_flow

NONLOCAL = ["material.rheology=nonlocal", "time.output_times=[]"]


def beads_law():
    config = load_config("incline-mu-i", NONLOCAL)
    return nonlocal_law(config.material, config.numerics.eps)


def test_local_limit_reaches_bagnold_profile() -> None:
    problem = build_plug_flow(load_config("incline-mu-i", [
        *NONLOCAL, "material.nonlocal_amplitude=0", "initial.fluidity=1",
        "material.viscosity=1e-6", "geometry.slope_deg=23", "time.dt=5e-3", "time.t_end=3"]))
    problem.simulation.run()
    law = beads_law()
    bagnold_ = bagnold(height=0.01, slope_deg=23.0,
                       inertial_number=law.local_inertial_number(math.tan(math.radians(23.0))),
                       grain_diameter=law.grain_diameter, packing=1500.0 / law.grain_density)
    z, u, _ = problem.profile(problem.simulation.t)
    ref = bagnold_(z)
    l2 = math.sqrt(np.trapezoid((u[:, 0] - ref) ** 2, z) / np.trapezoid(ref**2, z))
    assert 1e-6 < l2 < 1e-3, l2


def growth_rate(slope: float, factor: float) -> float:
    """The log-slope of ||g|| over t = 0.4-1 s, from g = 1e-3 of the local state's."""
    h = factor * beads_law().stopping_height(slope)
    size = h / 8
    problem = build_plug_flow(load_config("incline-mu-i", [
        *NONLOCAL, f"mesh.size={size}", f"geometry.length={2 * size}", f"geometry.height={h}",
        "initial.plug_base=0", "initial.shear_rate=0", "initial.fluidity=1e-3",
        f"geometry.slope_deg={slope}", "time.dt=0.01", "time.t_end=1.0"]))
    return fluidity_growth_rate(problem.solver, problem.simulation, problem.mesh, after=0.4)

@pytest.mark.parametrize("slope", [22.0, 25.0, 28.0, 30.0])
def test_the_rest_state_loses_stability_at_the_stopping_height(slope: float) -> None:
    below, above = growth_rate(slope, 0.9), growth_rate(slope, 1.1)
    assert below < 0 < above, (below, above)
    # rate ~ c (1 / h_stop^2 - 1 / h^2): its zero in x = 1 / h^2
    x_below, x_above = 1 / 0.9**2, 1 / 1.1**2
    x_zero = x_below + (x_above - x_below) * below / (below - above)
    assert 1 / math.sqrt(x_zero) == pytest.approx(1.0, abs=0.05)
