"""Collapse of a granular column over a rigid or erodible bed (configuration (b), sections 3
and 5): the builder, registered as the problem kind "column". It assembles the mesh, the
discretisation on it (solver and ALE mover, ``column_discretisation``), the remesher
(``column_remesher``) and the loop, starts from the column at rest, and adds to the loop the
parts that declare the outputs as named callbacks: the collapse's measures
(``column_measures``), an erodible layer (``column_layer``), a hysteretic friction's
state (``mobilisation``), a nonlocal law's fluidity (``fluidity``) and a packing fraction
(``packing``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.ale.column_mover import ColumnMover
from granflow.ale.remesh import boundary_edge_sizes
from granflow.ale.size_field import SizeField
from granflow.config import Config
from granflow.diagnostics.inertial import InertialNumbers
from granflow.fem.flow import FlowSolver
from granflow.geometry.domains import Polygon
from granflow.geometry.mesh import MESHER_FAILURES, polygon_mesh
from granflow.physics import gravity_vector
from granflow.scenarios.collapse_state import CheckpointedCollapse
from granflow.scenarios.column_discretisation import ColumnDiscretisation, discretise
from granflow.scenarios.column_layer import LayerTracking
from granflow.scenarios.column_measures import ColumnMeasures
from granflow.scenarios.column_remesher import ColumnRemesher
from granflow.scenarios.column_setup import ColumnSetup
from granflow.scenarios.column_sizes import initial_size_field
from granflow.scenarios.fluidity import FluidityOutputs
from granflow.scenarios.mobilisation_tracking import MobilisationTracking
from granflow.scenarios.packing import PackingOutputs
from granflow.scenarios.registry import register
from granflow.simulation.callbacks import add_callback
from granflow.simulation.rest import RestCriterion
from granflow.simulation.simulation import Simulation
from granflow.simulation.timestep import step_policy
from granflow.state.spec import instance

MESH = instance(ngs.Mesh, "a mesh", lambda mesh: {"cells": mesh.ne, "vertices": mesh.nv})


@dataclass
class ColumnCollapse(CheckpointedCollapse):
    """The assembled collapse, as the runner sees it (``runner.Problem``)."""

    setup: ColumnSetup
    current: ColumnDiscretisation
    simulation: Simulation
    remesher: ColumnRemesher
    measures: ColumnMeasures
    layer: LayerTracking | None = None
    mobilisation: MobilisationTracking | None = None   # a hysteretic friction's state

    @property
    def config(self) -> Config:
        return self.setup.config

    @property
    def polygon(self) -> Polygon:
        """The labelled initial domain."""
        return self.setup.scene.polygon

    @property
    def mesh(self) -> ngs.Mesh:
        return self.current.mesh

    @property
    def solver(self) -> FlowSolver:
        return self.current.solver

    @property
    def mover(self) -> ColumnMover:
        return self.current.mover

    @property
    def inertial(self) -> InertialNumbers | None:
        return self.measures.inertial

    # --- checkpoint (io/run_state.py; the sequence is collapse_state.py's) ----------
    def saved_mesh(self) -> ngs.Mesh:
        return self.mesh

    def mesh_share(self) -> Any:
        return MESH

    def rebuilt(self, mesh: ngs.Mesh) -> ColumnDiscretisation:
        return discretise(self.setup, mesh)


def build_column(config: Config) -> ColumnCollapse:
    """Netgen mesh of the column, friction walls, ALE mover, rest state with hydrostatic p."""
    setup = ColumnSetup.of(config)
    field = initial_size_field(setup, setup.layer_end(config.geometry.width))
    current, local = _first_discretisation(setup, field)
    layer = LayerTracking.start(setup, current) if setup.erodible else None
    if layer is not None:
        current.set_fraction(layer.material)
    pressure = _hydrostatic(setup, current.mesh, local)
    current.solver.set_state(ngs.CF((0.0, 0.0)), pressure)          # at rest, hydrostatic
    simulation = Simulation(solver=current.solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations,
                            mesh_motion=current.mover,
                            mesher_failures=MESHER_FAILURES,
                            velocity_floor=config.numerics.velocity_floor)
    remesher = ColumnRemesher(setup, current, simulation, layer=layer, size_field=field)
    measures = ColumnMeasures(setup, current, remesher, simulation,
                              inertial=InertialNumbers.of(current.solver.rheology))
    simulation.remesher = remesher
    mobilisation = None
    if current.mobilisation is not None:
        mobilisation = remesher.mobilisation = MobilisationTracking(setup.materials, current,
                                                                    simulation)
        mobilisation.start()
    # before the runner's outputs: they read the moved layer and the advanced state
    add_callback(simulation, measures, "collapse")
    fluidity, packing = FluidityOutputs.of(current), PackingOutputs.of(current)
    for name, part in (("layer", layer), ("mobilisation", mobilisation),
                       ("fluidity", fluidity), ("packing", packing)):
        if part is not None:
            add_callback(simulation, part, name)
    if config.time.stop_at_rest:
        simulation.stop_criteria = [RestCriterion(measures.flowing_fraction,
                                                  config.time.rest_fraction,
                                                  config.time.rest_duration)]
    return ColumnCollapse(setup=setup, current=current, simulation=simulation,
                          remesher=remesher, measures=measures, layer=layer,
                          mobilisation=mobilisation)


def _first_discretisation(setup: ColumnSetup, field: SizeField | None,
                          ) -> tuple[ColumnDiscretisation, np.ndarray]:
    """The first mesh of the scene's initial domain (a built-in shape meshed in its frame,
    then turned onto the bed profile), sized by the layer or by the size field ``field``,
    the solver and mover on it, and its vertices in the frame it was meshed in."""
    scene, config = setup.scene, setup.config
    polygon = scene.local or scene.polygon
    sizes = setup.layer_edge_sizes() if field is None else field.edge_size(scene.bed.height)
    restrict = None
    if field is not None:      # the size field's points, in the frame the shape is meshed in
        points = field.restrictions(scene.bed.z)
        restrict = np.column_stack([scene.to_local(points[:, :2]), points[:, 2]])
    mesh = polygon_mesh(polygon.points, polygon.labels,
                        config.mesh.size if field is None else field.maxh,
                        boundary_edge_sizes(scene.to_lab(np.asarray(polygon.points)), sizes),
                        interior=[(i, j, setup.layer_cell_size()) for i, j in polygon.interior],
                        stretch=setup.stretch, restrict=restrict)
    xy = mesh.ngmesh.Coordinates()
    local = xy.copy()
    if scene.frame is not None:                 # turned onto the bed profile
        xy[:] = scene.to_lab(local)
    return discretise(setup, mesh), local


def _hydrostatic(setup: ColumnSetup, mesh: ngs.Mesh, xy: np.ndarray) -> ngs.GridFunction:
    """The pressure at rest, -rho g_n (depth below the surface) at the vertices ``xy`` (in
    the frame the domain was meshed in): for a built-in shape the depths across the bed in
    the shape's frame, for a user's mass vertical depths; with a layer of its own density,
    the column's weight down to the layer's top and the layer's below it."""
    scene, config = setup.scene, setup.config
    force = gravity_vector(config.material.gravity, config.geometry.slope_deg)
    polygon = scene.local or scene.polygon
    top: Any = None
    if scene.local is not None:
        g_n = force[1] if scene.frame is None else float(np.dot(force, scene.frame[2]))
    else:
        g_n = force[1]
        top = scene.layer_top if scene.layer > 0 else None
    heights = np.array([polygon.surface_height(x) for x in xy[:, 0]])
    z = xy[:, 1]
    depth = np.maximum(heights - z, 0)
    pressure = ngs.GridFunction(ngs.H1(mesh, order=1))
    layer = setup.materials.layer
    if layer is None:
        pressure.vec.FV().NumPy()[:] = -config.material.density * g_n * depth
        return pressure
    lid = top(xy[:, 0]) if top is not None else config.geometry.erodible_thickness
    in_layer = np.clip(lid - z, 0.0, depth)
    pressure.vec.FV().NumPy()[:] = -g_n * (config.material.density * (depth - in_layer)
                                           + layer.density * in_layer)
    return pressure


register("column", build_column, figures=(*ColumnMeasures.figures, *LayerTracking.figures))
