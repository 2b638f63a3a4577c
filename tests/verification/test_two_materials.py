"""A column over a layer of its own material ([layer]): the tracked indicator across a
remesh, two materials that hold their load, and a weak column over a strong layer.

Coarse and short (a 1 cm layer, 4 cm cells, tenths of a second): what is checked does not
need resolution, only that the materials keep their identity and their laws."""

from __future__ import annotations

from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest
import shapely

from granflow.config import load_config
from granflow.fem.engine import NGSOLVE_OPS, read_on_walls
from granflow.fem.sampling import triangles
from granflow.geometry.mesh import BED, signed_areas
from granflow.io.checkpoint import read_checkpoint, write_checkpoint
from granflow.io.run_dir import RunDir
from granflow.io.run_state import SimulationState
from granflow.physics.regions import TwoMaterials
from granflow.scenarios.column import ColumnCollapse, build_column

BASE = ["mesh.size=0.04", "geometry.erodible_thickness=0.01", "mesh.layer_cells=2",
        "geometry.bed_length=0.5", "time.output_times=[]", "surface_tension.enabled=false",
        "time.stop_at_rest=false"]


def collapse(*overrides: str) -> ColumnCollapse:
    return build_column(load_config("trapezoid-erodible", [*BASE, *overrides]))


def indicator_area(problem: ColumnCollapse) -> float:
    """Integral of the indicator over the mesh: sum of fraction x triangle area."""
    assert problem.current.fraction is not None
    return float(problem.current.fraction.vec.FV().NumPy() @ signed_areas(problem.mesh))


def test_the_indicator_crosses_a_remesh_with_the_layer_area() -> None:
    """After a flow and a forced remesh, the indicator of the new mesh integrates to the
    tracked layer inside the new domain; the change is at most the area between the old and
    the new boundary (the region itself does not depend on the mesh)."""
    problem = collapse("material.friction_angle_deg=20", "layer.friction_angle_deg=30",
                       "time.t_end=0.05")
    problem.simulation.run()
    layer = problem.layer
    assert layer is not None
    before = indicator_area(problem)
    domain_before = layer.domain()
    exact = shapely.intersection(layer.material.region(), layer.domain()).area
    assert before == pytest.approx(exact, rel=1e-10)
    line = layer.material.line.copy()
    problem.remesher.remesh()
    after = indicator_area(problem)
    moved_boundary = shapely.symmetric_difference(domain_before, layer.domain()).area
    np.testing.assert_array_equal(layer.material.line, line)
    assert after == pytest.approx(
        shapely.intersection(layer.material.region(), layer.domain()).area, rel=1e-10)
    assert abs(after - before) <= moved_boundary + 1e-12 * before
    fractions = problem.current.fraction.vec.FV().NumPy()
    assert len(fractions) == len(triangles(problem.mesh))
    drift = after / layer.material.initial_area - 1
    assert abs(drift) < 1e-2, drift


def test_two_materials_that_hold_stay_at_rest() -> None:
    """A column (60 deg, 1550 kg/m^3) on a layer of another material (55 deg, 1800 kg/m^3),
    60-degree bed and wall: both hold their load; in 0.05 s nothing moves beyond the
    regularisation's creep (eps = 1e-6 1/s: a rigid-body test of one material reaches
    3e-7 m/s)."""
    problem = collapse("material.friction_angle_deg=60", "boundary.bed_friction_deg=60",
                       "boundary.wall_friction_deg=60", "layer.friction_angle_deg=55",
                       "layer.density=1800", "time.t_end=0.05")
    problem.simulation.run()
    layer = problem.layer
    assert layer is not None and problem.current.fraction is not None
    speed = np.hypot(*layer.marker_velocity.T)
    assert speed.max() < 1e-6
    assert layer.material.travel.max() < 1e-7
    assert np.abs(layer.material.line[:, 1] - 0.01).max() < 1e-7


def test_a_weak_column_slides_over_a_strong_layer_and_leaves_it_in_place() -> None:
    """A 20-degree column over a 60-degree layer spreads, and the layer stays: far less of it
    moves than under the same column with a layer of its own weak material."""
    runs = {}
    for name, layer_angle in (("strong", 60), ("weak", 20)):
        problem = collapse("material.friction_angle_deg=20", "boundary.bed_friction_deg=20",
                           f"layer.friction_angle_deg={layer_angle}", "time.t_end=0.15")
        problem.simulation.run()
        assert problem.layer is not None
        runs[name] = problem.layer.measures()
    strong, weak = runs["strong"], runs["weak"]
    assert strong["column_front_x"] > 0.297 + 0.02           # the column spread
    assert weak["layer_displaced_area"] > 2e-4                # a weak layer is dragged along
    assert strong["layer_displaced_area"] < 0.1 * weak["layer_displaced_area"]
    assert strong["erosion_depth_max"] <= 0.25 * 0.01 + 1e-12   # at most the top row


def test_a_restored_run_has_the_same_layer_and_goes_on(tmp_path: Path) -> None:
    """Through the checkpoint file (data only): the tracked layer, its sampled velocities
    and the indicator on the saved mesh come back exactly; the restored run continues."""
    materials = ("material.friction_angle_deg=20", "layer.friction_angle_deg=30",
                 "layer.density=1450")
    first = collapse(*materials, "time.t_end=0.02")
    first.simulation.run()
    run_dir = RunDir.create(tmp_path / "run")
    write_checkpoint(run_dir, SimulationState(loop=first.simulation.save_state(),
                                              scenario=first.save_state(), outputs={}))
    saved = read_checkpoint(run_dir.root)
    twin = collapse(*materials, "time.t_end=0.03")
    twin.restore_state(saved.scenario)
    twin.simulation.restore_state(saved.loop)
    assert first.layer is not None and twin.layer is not None
    for name in ("line", "markers", "origins", "travel"):
        np.testing.assert_array_equal(getattr(twin.layer.material, name),
                                      getattr(first.layer.material, name))
    np.testing.assert_array_equal(twin.layer.marker_velocity, first.layer.marker_velocity)
    assert first.current.fraction is not None and twin.current.fraction is not None
    np.testing.assert_array_equal(twin.current.fraction.vec.FV().NumPy(),
                                  first.current.fraction.vec.FV().NumPy())
    result = twin.simulation.run()
    assert result.status == "completed" and twin.simulation.t == pytest.approx(0.03)
    assert np.abs(twin.layer.material.markers - first.layer.material.markers).max() > 0


def test_in_r_z_the_layer_is_measured_by_its_volume_of_revolution() -> None:
    """A cylinder's layer (radius L, thickness h_e) holds pi L^2 h_e: its markers' rings add
    up to it and the tracked region inside the domain is that at t = 0 (drift 0)."""
    problem = build_column(load_config("cylinder-erodible", [
        "mesh.size=0.03", "geometry.bed_length=0.3", "time.output_times=[]"]))
    layer = problem.layer
    assert layer is not None
    he, length = 0.005, 0.3
    volume = np.pi * length**2 * he
    assert layer.marker_weights().sum() == pytest.approx(volume, rel=1e-12)
    assert layer.size(shapely.box(0, 0, length, he)) == pytest.approx(volume, rel=1e-12)
    assert layer.size(shapely.box(0, 0, length, he)) != pytest.approx(length * he)
    assert abs(layer.measures()["layer_area_drift"]) < 1e-12


def test_the_walls_see_the_layer_material_under_them() -> None:
    """The bed lies under the layer: the share of layer material the Coulomb friction's load
    reads there is 1 (the plain piecewise constant field reads 0 on the boundary, and the
    fixed point's wall term would take the column's law), and the blended law on the bed is
    the layer's."""
    problem = collapse("material.friction_angle_deg=20", "layer.friction_angle_deg=30")
    law = problem.solver.rheology
    assert isinstance(law, TwoMaterials)
    mesh = problem.mesh
    on_bed = ngs.ds(definedon=mesh.Boundaries(BED))
    assert ngs.Integrate(law.fraction * on_bed, mesh) == 0.0
    law = read_on_walls(law)              # what the wall term reads (fem/engine.py)
    assert ngs.Integrate(law.fraction * on_bed, mesh) == pytest.approx(0.5, rel=1e-12)
    pressure, rate = ngs.CF(100.0), ngs.CF(1.0)
    blended = ngs.Integrate(law.effective_viscosity_sq(rate, pressure, NGSOLVE_OPS) * on_bed,
                            mesh)
    layer = ngs.Integrate(law.layer.effective_viscosity_sq(rate, pressure, NGSOLVE_OPS)
                          * on_bed, mesh)
    assert blended == pytest.approx(layer, rel=1e-12)
