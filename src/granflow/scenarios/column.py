"""Collapse of a granular column over a rigid or erodible bed (configuration (b), sections 3
and 5): the builder, registered as the problem kind "column". It assembles the mesh, the
discretisation on it (solver and ALE mover, ``column_discretisation``), the remesher
(``column_remesher``) and the loop, starts from the column at rest, and adds to the loop the
parts that declare the outputs as named callbacks: the collapse's measures
(``column_measures``), an erodible layer (``column_layer``), a hysteretic friction's
state (``mobilisation``) and a nonlocal law's fluidity (``fluidity``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.ale.column_mover import ColumnMover
from granflow.ale.remesh import boundary_edge_sizes
from granflow.config import Config
from granflow.diagnostics.inertial import InertialNumbers
from granflow.fem.flow import FlowSolver
from granflow.geometry.domains import Polygon
from granflow.geometry.mesh import polygon_mesh
from granflow.geometry.scene import Scene, build_scene
from granflow.physics import MuI, gravity_vector
from granflow.physics.well_posedness import well_posed_window
from granflow.scenarios.column_discretisation import (
    ColumnDiscretisation,
    discretise,
    layer_cell_size,
    layer_edge_sizes,
    layer_end,
    layer_stretch,
)
from granflow.scenarios.column_layer import LayerTracking
from granflow.scenarios.column_measures import ColumnMeasures
from granflow.scenarios.column_remesher import ColumnRemesher
from granflow.scenarios.column_sizes import initial_size_field
from granflow.scenarios.fluidity import FluidityOutputs
from granflow.scenarios.materials import layer_material
from granflow.scenarios.mobilisation_tracking import MobilisationTracking
from granflow.scenarios.registry import register
from granflow.simulation.callbacks import add_callback
from granflow.simulation.rest import RestCriterion
from granflow.simulation.simulation import Simulation
from granflow.simulation.state_spec import Share, instance, record
from granflow.simulation.timestep import step_policy

MESH = instance(ngs.Mesh, "a mesh", lambda mesh: {"cells": mesh.ne, "vertices": mesh.nv})


@dataclass
class ColumnCollapse:
    """The assembled collapse, as the runner sees it (``runner.Problem``)."""

    config: Config
    polygon: Polygon
    current: ColumnDiscretisation
    simulation: Simulation
    remesher: ColumnRemesher
    measures: ColumnMeasures
    layer: LayerTracking | None = None
    mobilisation: MobilisationTracking | None = None   # a hysteretic friction's state

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

    # --- checkpoint (io/run_state.py) ---------------------------------------------
    def save_state(self) -> dict[str, Any]:
        """The scenario's share of the run state: the mesh (with its boundary labels, which
        deposition changes), the flow history, the mover and the remeshes' record, then the
        shares of the loop's callbacks (the diagnostics history, a layer, a mobilisation
        state; animation frames are files, ``frames/``)."""
        return {"mesh": self.mesh, "fields": self.solver.save_history(),
                "mover": self.mover.save_state(), **self.remesher.save_state(),
                **self.simulation.callbacks.save_state()}

    def share(self) -> Share:
        """What the members of ``save_state`` may be (in a checkpoint): its parts' shares."""
        return {"mesh": MESH, "fields": record(self.solver.history_share()),
                "mover": record(ColumnMover.share), **ColumnRemesher.share,
                **self.simulation.callbacks.shares()}

    def restore_state(self, state: dict[str, Any]) -> None:
        """Continue from ``save_state``: solver and mover rebuilt on the saved mesh, then
        the callbacks' shares on them."""
        restored = discretise(self.config, state["mesh"])
        restored.solver.restore_history(state["fields"])
        restored.mover.restore_state(state["mover"])
        self.current.replace(restored)
        self.simulation.replace(restored.solver, restored.mover)
        self.remesher.restore_state(state)
        self.simulation.callbacks.restore_state(state)


def _inertial_numbers(law: object) -> InertialNumbers | None:
    """mu(I) runs record their inertial numbers and the law's well-posed window (with a
    hysteretic friction, those of its flow law)."""
    law = getattr(law, "flow", law)
    if not isinstance(law, MuI):
        return None
    return InertialNumbers(well_posed=well_posed_window(law))


def build_column(config: Config) -> ColumnCollapse:
    """Netgen mesh of the column, friction walls, ALE mover, rest state with hydrostatic p."""
    geo, mat = config.geometry, config.material
    scene = column_scene(config)
    polygon = scene.local or scene.polygon      # a built-in shape: meshed in its frame
    fine = layer_cell_size(config) if geo.erodible_thickness > 0 else config.mesh.size
    field = initial_size_field(config, layer_end(config, geo.width))
    sizes = layer_edge_sizes(config) if field is None else field.edge_size(scene.bed.height)
    restrict = None
    if field is not None:      # the size field's points, in the frame the shape is meshed in
        points = field.restrictions(scene.bed.z)
        restrict = np.column_stack([scene.to_local(points[:, :2]), points[:, 2]])
    mesh = polygon_mesh(polygon.points, polygon.labels,
                        config.mesh.size if field is None else field.maxh,
                        boundary_edge_sizes(scene.to_lab(np.asarray(polygon.points)), sizes),
                        interior=[(i, j, fine) for i, j in polygon.interior],
                        stretch=layer_stretch(config), restrict=restrict)
    xy = mesh.ngmesh.Coordinates()
    local = xy.copy()
    if scene.frame is not None:                 # and turned onto the bed profile
        xy[:] = scene.to_lab(local)
    current = discretise(config, mesh)
    layer = LayerTracking.start(config, current) if geo.erodible_thickness > 0 else None
    if layer is not None:
        current.set_fraction(layer.material)
    force = gravity_vector(mat.gravity, geo.slope_deg)
    if scene.local is not None:     # depths across the bed, in the shape's frame
        g_n = force[1] if scene.frame is None else float(np.dot(force, scene.frame[2]))
        heights = np.array([polygon.surface_height(x) for x in local[:, 0]])
        top = None
    else:                           # a user's mass: vertical depths
        g_n, heights = force[1], np.array([polygon.surface_height(x) for x in xy[:, 0]])
        local = xy
        top = scene.layer_top if scene.layer > 0 else None
    pressure = ngs.GridFunction(ngs.H1(mesh, order=1))
    pressure.vec.FV().NumPy()[:] = _hydrostatic(config, g_n, heights, local, top)
    current.solver.set_state(ngs.CF((0.0, 0.0)), pressure)          # at rest, hydrostatic
    simulation = Simulation(solver=current.solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations,
                            mesh_motion=current.mover,
                            velocity_floor=config.numerics.velocity_floor)
    remesher = ColumnRemesher(config, current, simulation, layer=layer, size_field=field)
    measures = ColumnMeasures(config, current, remesher, simulation,
                              inertial=_inertial_numbers(current.solver.rheology))
    simulation.remesher = remesher
    mobilisation = None
    if current.mobilisation is not None:
        mobilisation = remesher.mobilisation = MobilisationTracking(config, current, simulation)
        mobilisation.start()
    # before the runner's outputs: they read the moved layer and the advanced state
    add_callback(simulation, measures, "collapse")
    fluidity = FluidityOutputs(current) if current.solver.fluidity is not None else None
    for name, part in (("layer", layer), ("mobilisation", mobilisation),
                       ("fluidity", fluidity)):
        if part is not None:
            add_callback(simulation, part, name)
    if config.time.stop_at_rest:
        simulation.stop_criteria = [RestCriterion(measures.flowing_fraction,
                                                  config.time.rest_fraction,
                                                  config.time.rest_duration)]
    return ColumnCollapse(config=config, polygon=scene.polygon, current=current,
                          simulation=simulation, remesher=remesher, measures=measures,
                          layer=layer, mobilisation=mobilisation)


def column_scene(config: Config) -> Scene:
    """The bed, the walls and the initial domain (``geometry/scene.py``): the meshed layer
    ends at ``layer_end``; a layer of its own material starts with its top under the column
    as an interior line of the mesh."""
    geo = config.geometry
    return build_scene(geo, config.gate, layer_end(config, geo.width),
                       interface=layer_material(config) is not None)


def _hydrostatic(config: Config, g_z: float, heights: np.ndarray, xy: np.ndarray,
                 layer_top: Any = None) -> np.ndarray:
    """The pressure at rest: -rho g_z (depth below the surface); with a layer of its own
    density, the column's weight down to the layer's top and the layer's below it."""
    z = xy[:, 1]
    depth = np.maximum(heights - z, 0)
    layer = layer_material(config)
    if layer is None:
        return -config.material.density * g_z * depth
    top = layer_top(xy[:, 0]) if layer_top is not None else config.geometry.erodible_thickness
    in_layer = np.clip(top - z, 0.0, depth)
    return -g_z * (config.material.density * (depth - in_layer) + layer.density * in_layer)


register("column", build_column, figures=(*ColumnMeasures.figures, *LayerTracking.figures))
