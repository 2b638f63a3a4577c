"""A slab launched down a periodic incline: the erosion mechanism isolated from the collapse.

A slab of thickness ``geometry.height`` moves at ``initial.slab_speed`` along the rigid bed
(``boundary.bed``), or along a layer of thickness ``geometry.erodible_thickness`` at rest on
that bed (of the slab's material, or of ``[layer]``'s). Everything is uniform along the bed
(a periodic strip of ``geometry.length``): the flow is a shear flow u_x(z, t), the mesh does
not move, and what the slab travels until it stops against what it travels on the bed alone
says whether a layer lengthens or shortens a runout, in seconds of computing. The builder,
registered as the problem kind "slab", and its outputs (``SlabMeasures``: the slab's and the
layer's mean speeds and distances, the bed's slip, the displacement at each level).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import ngsolve as ngs
import numpy as np

from granflow.config import Config
from granflow.fem.flow import FlowSolver
from granflow.fem.flow_factory import build_flow
from granflow.fem.mobilisation_field import MobilisationField
from granflow.fem.sampling import cell_means, triangles, vertex_samples
from granflow.geometry.mesh import BED, SURFACE, stacked_layer_mesh
from granflow.physics import gravity_vector
from granflow.scenarios.bed import bed_wall, rough_bed
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.fluidity import FluidityOutputs
from granflow.scenarios.materials import run_materials, share_of
from granflow.scenarios.mobilisation_tracking import MobilisationTracking, mobilisation_of
from granflow.scenarios.packing import PackingOutputs
from granflow.scenarios.registry import register
from granflow.simulation.callbacks import add_callback
from granflow.simulation.outputs import Outputs, Table
from granflow.simulation.rest import RestCriterion
from granflow.simulation.simulation import RunResult, Simulation
from granflow.simulation.timestep import step_policy
from granflow.state.spec import TIME, Share, array, assign, or_none, record

FLOWING_SPEED = 1e-3   # m/s: material moves above it (paper section 5.1.2)


@dataclass
class Slab:
    """The assembled slab problem (``runner.Problem``): mesh, solver, loop and its parts."""

    config: Config
    mesh: ngs.Mesh
    solver: FlowSolver
    simulation: Simulation

    @property
    def fraction(self) -> ngs.GridFunction | None:
        """A layer of its own material: its share per triangle (else None)."""
        return share_of(self.solver)

    @property
    def mobilisation(self) -> MobilisationField | None:
        """A hysteretic friction's state (else None)."""
        return mobilisation_of(self.solver)

    def save_state(self) -> dict[str, Any]:
        """The flow's history and the shares of the loop's callbacks (the mesh never moves)."""
        return {"fields": self.solver.save_history(), **self.simulation.callbacks.save_state()}

    def share(self) -> Share:
        return {"fields": record(self.solver.history_share()),
                **self.simulation.callbacks.shares()}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.solver.restore_history(state["fields"])
        self.simulation.callbacks.restore_state(state)


def slab_figure(run_dir: Any, config: Config) -> None:
    """Speeds against time, velocity and displacement across the strip
    (``io/slab_plots.py``)."""
    from granflow.io.slab_plots import plot_slab

    plot_slab(run_dir, config)


@dataclass
class SlabMeasures(Outputs):
    """What the slab's run measures (module docstring): each step the mean speed along the
    bed of the slab's material and of the layer's, the bed's slip and the surface's speed,
    and their distances (the trapezoidal rule over the accepted steps); the displacement of
    each level of mesh nodes; at the end the summary's ``slab_distance_m`` (also
    ``runout_m``), ``slab_speed_m_s``, ``layer_distance_m``, ``layer_moved_depth_m`` (how
    deep the layer's material moved by more than a grain diameter) and ``stop_time_s``
    (since when the slab's mean speed has stayed below 1 mm/s, None while it moves)."""

    columns = ("slab_speed", "slab_distance", "layer_speed", "layer_distance", "bed_slip",
               "surface_speed")
    figures = (slab_figure,)
    share: ClassVar[Share] = {"slab": record({
        "t": TIME, "slab_distance": or_none(TIME), "layer_distance": or_none(TIME),
        "speeds": array(2), "displacement": array("levels"),
        "rest_since": or_none(TIME)})}

    problem: Slab
    layer_thickness: float
    grain_diameter: float
    t: float = 0.0
    slab_distance: float = 0.0
    layer_distance: float = 0.0
    rest_since: float | None = None
    _speeds: np.ndarray = field(init=False, repr=False)   # slab, layer at t
    _levels: np.ndarray = field(init=False, repr=False)   # z of each level of nodes
    _level_of: np.ndarray = field(init=False, repr=False)   # each vertex's level
    _displacement: np.ndarray = field(init=False, repr=False)
    _level_speeds: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        mesh = self.problem.mesh
        z = mesh.ngmesh.Coordinates()[:, 1]
        self._levels, self._level_of = np.unique(np.round(z, 12), return_inverse=True)
        self._displacement = np.zeros(len(self._levels))
        self._speeds = self._mean_speeds()
        self._level_speeds = self._speeds_by_level()

    # --- measures of the accepted state -----------------------------------------------
    def _mean_speeds(self) -> np.ndarray:
        """The mean u_x of the slab's material and of the layer's (0 without a layer)."""
        u_x = self.problem.solver.velocity[0]
        mesh = self.problem.mesh
        above = ngs.IfPos(ngs.y - self.layer_thickness, 1.0, 0.0)
        length = mesh_length(mesh)
        slab = ngs.Integrate(u_x * above, mesh, order=4) / (
            length * (self._top() - self.layer_thickness))
        if self.layer_thickness == 0:
            return np.array([slab, 0.0])
        layer = ngs.Integrate(u_x * (1.0 - above), mesh, order=4) / (
            length * self.layer_thickness)
        return np.array([slab, layer])

    def _top(self) -> float:
        return float(self.problem.mesh.ngmesh.Coordinates()[:, 1].max())

    def _speeds_by_level(self) -> np.ndarray:
        """u_x at each level of nodes (the mean over its vertices: uniform along the bed)."""
        u_x = vertex_samples(self.problem.mesh, self.problem.solver.velocity[0])
        return np.bincount(self._level_of, weights=u_x) / np.bincount(self._level_of)

    def _boundary_speed(self, label: str) -> float:
        mesh = self.problem.mesh
        u_x = self.problem.solver.velocity[0]
        return float(ngs.Integrate(u_x, mesh, ngs.BND, definedon=mesh.Boundaries(label))
                     / mesh_length(mesh))

    def flowing_fraction(self) -> float:
        """The share of the strip's area faster than 1 mm/s (the rest criterion's)."""
        speed, areas = cell_means(self.problem.mesh, ngs.Norm(self.problem.solver.velocity))
        return float(areas[speed > FLOWING_SPEED].sum() / areas.sum())

    # --- after each accepted step ------------------------------------------------------
    def __call__(self, sim: Simulation) -> None:
        dt = sim.t - self.t
        if dt <= 0:
            return
        speeds, levels = self._mean_speeds(), self._speeds_by_level()
        self.slab_distance += 0.5 * dt * float(self._speeds[0] + speeds[0])
        self.layer_distance += 0.5 * dt * float(self._speeds[1] + speeds[1])
        self._displacement += 0.5 * dt * (self._level_speeds + levels)
        self._speeds, self._level_speeds, self.t = speeds, levels, sim.t
        if abs(speeds[0]) > FLOWING_SPEED:
            self.rest_since = None
        elif self.rest_since is None:
            self.rest_since = sim.t

    def layer_moved_depth(self) -> float:
        """The depth of layer (from its top) whose material moved by more than a grain
        diameter (0 without a layer)."""
        if self.layer_thickness == 0:
            return 0.0
        below = self._levels <= self.layer_thickness * (1 + 1e-9)
        moved = below & (np.abs(self._displacement) > self.grain_diameter)
        if not moved.any():
            return 0.0
        return float(self.layer_thickness - self._levels[moved].min())

    # --- outputs -----------------------------------------------------------------------
    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        return {"slab_speed": float(self._speeds[0]), "slab_distance": self.slab_distance,
                "layer_speed": float(self._speeds[1]), "layer_distance": self.layer_distance,
                "bed_slip": self._boundary_speed(BED),
                "surface_speed": self._boundary_speed(SURFACE)}

    def profiles(self, t: float) -> dict[str, Table]:
        """u_x and the displacement at each level of nodes."""
        return {"slab": (["z", "u_x", "displacement"],
                         np.column_stack([self._levels, self._level_speeds,
                                          self._displacement]))}

    def summary(self, result: RunResult) -> dict[str, Any]:
        return {"slab_distance_m": self.slab_distance, "runout_m": self.slab_distance,
                "slab_speed_m_s": float(self._speeds[0]),
                "layer_distance_m": self.layer_distance if self.layer_thickness else None,
                "layer_moved_depth_m": self.layer_moved_depth(),
                "bed_slip_m_s": self._boundary_speed(BED),
                "surface_speed_m_s": self._boundary_speed(SURFACE),
                "stop_time_s": self.rest_since}

    def save_state(self) -> dict[str, Any]:
        return {"slab": {"t": self.t, "slab_distance": self.slab_distance,
                         "layer_distance": self.layer_distance, "speeds": self._speeds.copy(),
                         "displacement": self._displacement.copy(),
                         "rest_since": self.rest_since}}

    def restore_state(self, state: dict[str, Any]) -> None:
        saved = state["slab"]
        self.t = float(saved["t"])
        self.slab_distance = float(saved["slab_distance"] or 0.0)
        self.layer_distance = float(saved["layer_distance"] or 0.0)
        assign(self._speeds, saved["speeds"], "the slab's saved speeds")
        assign(self._displacement, saved["displacement"], "the saved displacements")
        self.rest_since = saved["rest_since"]
        self._level_speeds = self._speeds_by_level()


def mesh_length(mesh: ngs.Mesh) -> float:
    """The strip's length along the bed."""
    x = mesh.ngmesh.Coordinates()[:, 0]
    return float(x.max() - x.min())


def layer_share(mesh: ngs.Mesh, thickness: float) -> np.ndarray:
    """1 in the triangles of the layer (below ``thickness``), 0 in the slab's."""
    centres = mesh.ngmesh.Coordinates()[triangles(mesh)].mean(axis=1)[:, 1]
    return (centres < thickness).astype(float)


def initial_state(config: Config, force: tuple[float, float]
                  ) -> tuple[ngs.CoefficientFunction, ngs.CoefficientFunction]:
    """The slab at ``initial.slab_speed`` over the layer at rest, the hydrostatic pressure
    of the two (each of its density)."""
    geo = config.geometry
    materials = run_materials(config)
    he, top = geo.erodible_thickness, geo.erodible_thickness + geo.height
    z = ngs.y
    velocity = ngs.CF((ngs.IfPos(z - he, config.initial.slab_speed, 0.0), 0.0))
    rho, rho_layer = materials.column.density, materials.of_layer.density
    weight = -force[1]
    above = rho * (top - ngs.IfPos(z - he, z, he))          # slab material above z
    below = rho_layer * ngs.IfPos(he - z, he - z, 0.0)       # layer material above z
    return velocity, weight * (above + below)


def build_slab(config: Config) -> Slab:
    """Mesh, solver on the bed of ``boundary.bed``, the slab in motion over the layer at
    rest, the loop and its parts."""
    geo, mat, num, msh = config.geometry, config.material, config.numerics, config.mesh
    he = geo.erodible_thickness
    layers = ([(he, msh.layer_cells)] if he > 0 else []) + [
        (geo.height, max(1, round(geo.height / msh.size)))]
    cells_x = msh.cells_x or max(2, round(geo.length / msh.size))
    mesh = stacked_layer_mesh(geo.length, layers, cells_x)
    force = gravity_vector(mat.gravity, geo.slope_deg)
    materials = run_materials(config)
    layout = Layout(walls=(bed_wall(config),), periodic=True, rough=rough_bed(config))
    solver = build_flow(mesh, flow_spec(config, materials, layout))
    problem = Slab(config=config, mesh=mesh, solver=solver, simulation=Simulation(
        solver=solver, steps_policy=step_policy(config), t_end=config.time.t_end,
        max_iterations=num.max_iterations, velocity_floor=num.velocity_floor))
    if problem.fraction is not None:
        problem.fraction.vec.FV().NumPy()[:] = layer_share(mesh, he)
    solver.set_state(*initial_state(config, force))     # g = 0: a slab moving as a block
    simulation = problem.simulation
    measures = SlabMeasures(problem, he, materials.of_layer.grain_diameter)
    add_callback(simulation, measures, "slab")
    if config.time.stop_at_rest:
        simulation.stop_criteria = [RestCriterion(measures.flowing_fraction,
                                                  config.time.rest_fraction,
                                                  config.time.rest_duration)]
    fluidity, packing = FluidityOutputs.of(problem), PackingOutputs.of(problem)
    for name, part in (("fluidity", fluidity), ("packing", packing)):
        if part is not None:
            add_callback(simulation, part, name)
    if problem.mobilisation is not None:
        tracking = MobilisationTracking(materials, problem, simulation)
        tracking.start()
        add_callback(simulation, tracking, "mobilisation")
    return problem


register("slab", build_slab, figures=SlabMeasures.figures)
