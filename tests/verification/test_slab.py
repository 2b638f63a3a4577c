"""The slab kind and the rigid bed's laws against independent solutions.

- A block (a slab stronger than its bed) launched along a Coulomb bed decelerates at
  g (mu cos(theta) - sin(theta)) and stops after U0^2 / (2 a): the rigid block's mechanics;
  a dense block on the material bed at the friction of its packing, mu + K (phi - phi_c).
- A mu(I) layer over the material bed flows steadily as Bagnold's profile shifted by the
  bed's slip d gamma_dot(0) = I_theta sqrt(P_b / rho_s) (``physics/bed.py``).
- The no-slip bed's penalty gives the periodic layer's strong no-slip flow.
- A slab over a layer of its own Drucker-Prager material at rest, with a small viscosity,
  shears the layer's top only: the layer under it holds (the stress ratio inside it stays
  below mu_s, docs/erosion.md).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

import granflow
from granflow.config import load_config
from granflow.physics import MuI
from granflow.reference.incline import bagnold_profile
from granflow.scenarios.materials import build_rheology
from granflow.scenarios.plug_flow import build_plug_flow
from granflow.scenarios.slab import Slab, build_slab

COARSE = ["mesh.size=0.0025", "time.output_times=[]"]


def run_slab(overrides: list[str]) -> Slab:
    problem = build_slab(load_config("slab", COARSE + overrides))
    problem.simulation.run()
    return problem


def summary(problem: Slab) -> dict[str, float]:
    measures = problem.simulation.callbacks["slab"].func
    return {"distance": measures.slab_distance, "stop": measures.rest_since}


@pytest.mark.parametrize("slope", [0.0, 16.0])
def test_a_block_on_a_coulomb_bed_stops_where_the_rigid_block_does(slope: float) -> None:
    """Friction 35 deg inside, 25.5 deg on the bed: the slab slides without shearing. Its
    distance to rest within 1e-4 of U0^2 / (2 a) (implicit Euler is exact for a constant
    deceleration; measured 1.5e-7), its stop within two steps of U0 / a."""
    problem = run_slab(["material.friction_angle_deg=35", f"geometry.slope_deg={slope}",
                        "initial.slab_speed=0.8"])
    theta = math.radians(slope)
    a = 9.81 * (math.tan(math.radians(25.5)) * math.cos(theta) - math.sin(theta))
    got = summary(problem)
    assert got["distance"] == pytest.approx(0.8**2 / (2 * a), rel=1e-4)
    assert got["stop"] == pytest.approx(0.8 / a, abs=2 * problem.config.time.dt_max)
    assert problem.simulation.t < problem.config.time.t_end       # stopped at rest


def test_a_dense_block_on_the_material_bed_stops_where_its_dilatancy_puts_it() -> None:
    """The paper's material at phi_0 = 0.62 (1550 over grains of 2500) with a packing
    (phi_c = 0.60, K = 4, a = 0) and eta = 0.01 Pa s on the material bed at 10 deg: it
    slides as a block (it barely shears: phi stays within 1e-5 of phi_0) on a bed of
    friction tan 25.5 deg + K (phi_0 - phi_c), the material's; its distance within 5e-3 of
    that rigid block's U0^2 / (2 a) (measured 1.2e-3: the block is at its own friction
    inside), and not the 25.5-degree block's, 27 % further."""
    problem = run_slab(["material.packing=critical-state", "material.viscosity=0.01",
                        "boundary.bed=material"])
    theta, mu = math.radians(10.0), math.tan(math.radians(25.5)) + 4.0 * (0.62 - 0.60)
    a = 9.81 * (mu * math.cos(theta) - math.sin(theta))
    got = summary(problem)
    assert got["distance"] == pytest.approx(1.0 / (2 * a), rel=5e-3)
    packing = problem.simulation.callbacks["packing"].func.coupling.packing()
    assert np.max(np.abs(packing - 0.62)) < 1e-5


def test_a_mu_i_layer_over_the_material_bed_slips_by_its_basal_shear_over_a_grain() -> None:
    """Glass beads' mu(I) (eta = 1e-4 Pa s) at 23 deg over the material bed, started from
    Bagnold's profile plus the slip d gamma_dot(0): after 1 s the slip within 1 % and the
    surface within 1 % of that steady state. (A no-slip or a 25.5-degree Coulomb bed holds
    the base: no slip at all.)"""
    mu_i = ["material.rheology=mu-i", "material.density=1500", "material.viscosity=1e-4",
            "material.friction_angle_deg=20.9", "material.grain_diameter=0.0005",
            "geometry.slope_deg=23", "boundary.bed=material", "time.adaptive=false",
            "time.dt=5e-3", "time.t_end=1.0", "time.stop_at_rest=false",
            "mesh.size=0.00125"]
    problem = build_slab(load_config("slab", COARSE + mu_i))
    law = build_rheology(problem.config)
    assert isinstance(law, MuI)
    steady = bagnold_profile(height=0.01, slope_deg=23.0, law=dataclasses.replace(
        law, viscosity=0.0), density=1500.0)
    i_theta = law.inverse_friction(math.tan(math.radians(23.0)))
    slip = i_theta * math.sqrt(1500.0 * 9.81 * math.cos(math.radians(23.0)) * 0.01 / 2500.0)
    z = np.linspace(0.0, 0.01, 201)
    u0 = ngs.VoxelCoefficient((0.0, 0.0), (1.0, 0.01), (slip + steady(z))[:, None]
                              * np.ones((1, 2)), linear=True)
    pressure = 1500.0 * 9.81 * math.cos(math.radians(23.0)) * (0.01 - ngs.y)
    problem.solver.set_state(ngs.CF((u0, 0.0)), pressure)
    problem.simulation.run()
    measures = problem.simulation.callbacks["slab"].func
    bed, surface = measures._boundary_speed("bed"), measures._boundary_speed("surface")
    assert bed == pytest.approx(slip, rel=0.01)
    assert surface == pytest.approx(slip + float(steady(0.01)), rel=0.01)
    assert slip / surface > 0.05          # the slip is not negligible: the test sees it


def test_the_no_slip_penalty_gives_the_periodic_layers_no_slip_flow() -> None:
    """A Drucker-Prager layer at 25 deg (friction 20 deg, eta = 0.5 Pa s) from rest, 0.2 s:
    the slab on the no-slip bed (penalty) against the periodic layer (strong no-slip)."""
    common = ["material.friction_angle_deg=20", "material.viscosity=0.5", "material.density=1500",
              "geometry.slope_deg=25", "time.adaptive=false", "time.dt=5e-3", "time.t_end=0.2",
              "mesh.size=0.00125", "numerics.linearization=newton"]
    slab = run_slab([*common, "boundary.bed=no-slip", "initial.slab_speed=0.0",
                     "time.stop_at_rest=false"])
    layer = build_plug_flow(load_config("incline-mu-i", [
        *common, "material.rheology=drucker-prager", "time.output_times=[]",
        "mesh.cells_x=2", "geometry.length=0.002"]))
    layer.simulation.run()
    z = np.linspace(0.0, 0.01 - 1e-9, 41)
    u_slab = np.array([slab.solver.velocity(slab.mesh(0.001, zi))[0] for zi in z])
    u_layer = np.array([layer.solver.velocity(layer.mesh(0.001, zi))[0] for zi in z])
    assert u_layer.max() > 0.05                   # it flows
    assert np.max(np.abs(u_slab - u_layer)) < 1e-6 * u_layer.max()


def test_a_slab_over_a_weakly_viscous_layer_shears_only_the_layers_top() -> None:
    """Drucker-Prager (25.5 deg, eta = 0.01 Pa s) over 5 mm of it at rest on the 25.5-degree
    Coulomb bed at 10 deg: the layer below its top cell stays in place (moved < a grain
    diameter), and the slab travels less than the block on the bed (it shears) but more
    than a block that shared its momentum with the whole layer, (2/3)^2 of it (measured:
    0.86 of the block's)."""
    problem = run_slab(["geometry.erodible_thickness=0.005", "material.viscosity=0.01",
                        "mesh.layer_cells=4", "numerics.linearization=primal-dual"])
    measures = problem.simulation.callbacks["slab"].func
    theta = math.radians(10.0)
    block = 1.0 / (2 * 9.81 * (math.tan(math.radians(25.5)) * math.cos(theta)
                               - math.sin(theta)))
    assert measures.layer_moved_depth() <= 0.005 / 4 + 1e-12
    assert (2 / 3) ** 2 * block < measures.slab_distance < block


def test_a_slab_resumed_from_its_checkpoint_travels_as_the_uninterrupted_one(
        tmp_path: Path) -> None:
    """The slab's distances and displacements are in the checkpoint: a run stopped at
    0.06 s and extended to 0.12 s ends where the run to 0.12 s does."""
    case = {"geometry.erodible_thickness": 0.005, "time.stop_at_rest": False,
            "time.output_times": [], "output.progress": False}
    granflow.run("slab", {**case, "time.t_end": 0.06}, out=tmp_path / "a")
    resumed = granflow.resume(tmp_path / "a", {"time.t_end": 0.12}).summary.extra
    whole = granflow.run("slab", {**case, "time.t_end": 0.12, "time.output_times": [0.06]},
                         out=tmp_path / "b").summary.extra      # its steps end at 0.06 too
    for key in ("slab_distance_m", "layer_distance_m", "slab_speed_m_s"):
        assert resumed[key] == pytest.approx(whole[key], rel=1e-9), key
    assert whole["slab_distance_m"] > 0.05            # it moved
