"""The rigid bed's models on a collapse (``boundary.bed``, docs/model.md "The rigid bed").

- Drucker-Prager's material bed is its Coulomb bed at its friction angle: the same run to
  round-off (the paper's model of the glued beads, for a rate-independent law).
- On the no-slip bed the material does not slide: the bed's tangential velocity is the
  penalty's residual, and the front advances only as the surface lands on the bed.
- The nonlocal fluidity is 0 on a no-slip bed, whatever ``boundary.bed_fluidity`` says (the
  key is refused there as without effect).
- With a packing fraction the material bed's friction is the material's, mu + tan(psi):
  while phi is uniform (a slab's first step) Drucker-Prager's material bed is the Coulomb
  bed at the angle of tan(25.5 deg) + K (phi_0 - phi_c).
"""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np
import pytest

from granflow.config import ConfigError, load_config
from granflow.fem.sampling import vertex_samples
from granflow.geometry.mesh import BED
from granflow.scenarios.column import build_column
from granflow.scenarios.fluidity import fluidity_of
from granflow.scenarios.slab import build_slab

SHORT = ["mesh.size=0.035", "time.t_end=0.08", "time.output_times=[]",
         "time.stop_at_rest=false"]


def collapse(overrides: list[str]):
    problem = build_column(load_config("rectangle-rigid", SHORT + overrides))
    problem.simulation.run()
    return problem


def test_drucker_pragers_material_bed_is_its_coulomb_bed() -> None:
    coulomb, material = collapse([]), collapse(["boundary.bed=material"])
    assert material.simulation.step == coulomb.simulation.step
    np.testing.assert_allclose(material.mesh.ngmesh.Coordinates(),
                               coulomb.mesh.ngmesh.Coordinates(), rtol=0, atol=1e-12)
    assert coulomb.measures.front() > 0.21           # it moved


def test_the_no_slip_bed_holds_the_material_where_the_coulomb_bed_lets_it_slide() -> None:
    """Largest tangential speed on the bed at 0.25 s: the penalty's residual (tractions of
    ~100 Pa over xi = 1e12; measured 8e-10 m/s) on the no-slip bed, the sliding front's on
    the Coulomb bed (0.83 m/s)."""

    def bed_slip(problem) -> float:
        on_bed = np.abs(problem.mesh.ngmesh.Coordinates()[:, 1]) < 1e-12   # the level bed
        u = vertex_samples(problem.mesh, problem.solver.velocity)
        return float(np.max(np.abs(u[on_bed, 0])))

    later = ["time.t_end=0.25"]                  # the front slides on the Coulomb bed by then
    no_slip, coulomb = collapse(["boundary.bed=no-slip", *later]), collapse(later)
    assert bed_slip(no_slip) < 1e-6
    assert bed_slip(coulomb) > 0.1
    assert no_slip.measures.front() < coulomb.measures.front()


def test_the_fluidity_is_zero_on_a_no_slip_bed() -> None:
    nonlocal_ = ["material.rheology=nonlocal", "material.friction_angle_deg=20.9",
                 "geometry.slope_deg=22", "boundary.bed=no-slip", "time.t_end=0.01"]
    problem = collapse(nonlocal_)
    field = fluidity_of(problem.solver)
    assert field is not None
    on_bed = ngs.Integrate(field.previous**2, problem.mesh, ngs.BND,
                           definedon=problem.mesh.Boundaries(BED))
    inside = ngs.Integrate(field.previous**2, problem.mesh)
    assert inside > 0 and on_bed == 0.0
    with pytest.raises(ConfigError, match="boundary.bed_fluidity .* has no effect here"):
        load_config("rectangle-rigid", [*nonlocal_, "boundary.bed_fluidity=zero"])


def test_a_packings_material_bed_is_the_coulomb_bed_at_mu_plus_tan_psi() -> None:
    """The slab of the paper's material at phi_0 = 0.62 (its density 1550 over grains of
    2500), phi_c = 0.60, K = 4, a = 0, launched at 1 m/s on the bed at 10 deg, one step of
    5 ms (phi_0 everywhere while it is solved): on the material bed, the same step as on
    the Coulomb bed at atan(tan 25.5 deg + 0.08) = 29.1 deg to 1e-8 of the speed
    (measured: equal); the Coulomb bed at 25.5 deg (the bed without the packing's
    friction) differs by more than 1e-3 of it (measured: 3.9e-3)."""
    step = ["material.packing=critical-state", "time.adaptive=false", "time.dt=0.005",
            "time.t_end=0.005", "time.stop_at_rest=false", "time.output_times=[]"]
    angle = math.degrees(math.atan(math.tan(math.radians(25.5)) + 4.0 * (0.62 - 0.60)))

    def velocity(overrides: list[str]) -> np.ndarray:
        problem = build_slab(load_config("slab", [*step, *overrides]))
        problem.simulation.run()
        assert problem.simulation.step == 1
        return vertex_samples(problem.mesh, problem.solver.velocity)

    material = velocity(["boundary.bed=material"])
    coulomb = velocity([f"boundary.bed_friction_deg={angle!r}"])
    without = velocity([])
    speed = float(np.max(np.abs(coulomb)))
    assert speed > 0.9
    assert np.max(np.abs(material - coulomb)) < 1e-8 * speed
    assert np.max(np.abs(without - coulomb)) > 1e-3 * speed
