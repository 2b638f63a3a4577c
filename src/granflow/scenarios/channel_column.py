"""Collapse of a granular column in a channel, in three dimensions (``geometry.kind =
"column"`` with ``geometry.dimension = 3``): the builder, registered for 3D, and the
assembled problem. The column's section (the rectangle or the trapezoid) is extruded
across the channel (``scenarios/channel_setup.py``), meshed by Netgen, discretised with
Taylor-Hood P2/P1 and the regularised law (2.13) through the flow solver's factory and moved
by the ALE mover in the volume (``scenarios/channel_discretisation.py``); the remesher
(``scenarios/channel_remesher.py``) and the measures (``scenarios/channel_measures.py``)
join the loop, which stops at rest as the section's."""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from granflow.ale.channel_mover import ChannelMover
from granflow.config import Config
from granflow.fem.flow import FlowSolver
from granflow.geometry.mesh3d import (
    LOFT_FAILURES,
    extruded_mesh,
    mesh_arrays,
    mesh_from_arrays,
)
from granflow.scenarios.channel_discretisation import ChannelDiscretisation, discretise
from granflow.scenarios.channel_measures import ChannelMeasures
from granflow.scenarios.channel_remesher import ChannelRemesher
from granflow.scenarios.channel_setup import ChannelSetup
from granflow.scenarios.collapse_state import CheckpointedCollapse
from granflow.scenarios.registry import register
from granflow.simulation.callbacks import add_callback
from granflow.simulation.rest import RestCriterion
from granflow.simulation.simulation import Simulation
from granflow.simulation.timestep import step_policy
from granflow.state.spec import Share, array, record

MESH: Share = {"points": array(None, 3), "tetrahedra": array(None, 4, kind="i"),
               "faces": array(None, 3, kind="i"), "labels": array(None, kind="i")}


@dataclass
class ChannelCollapse(CheckpointedCollapse):
    """The assembled 3D collapse, as the runner sees it (``registry.Problem``)."""

    setup: ChannelSetup
    current: ChannelDiscretisation
    simulation: Simulation
    remesher: ChannelRemesher
    measures: ChannelMeasures

    @property
    def config(self) -> Config:
        return self.setup.config

    @property
    def mesh(self) -> ngs.Mesh:
        return self.current.mesh

    @property
    def solver(self) -> FlowSolver:
        return self.current.solver       # type: ignore[no-any-return]

    @property
    def mover(self) -> ChannelMover:
        return self.current.mover

    # --- checkpoint (io/run_state.py; the sequence is collapse_state.py's) ----------
    def saved_mesh(self) -> dict[str, np.ndarray]:
        """The mesh as arrays, with the labels deposition changes."""
        return mesh_arrays(self.mesh)

    def mesh_share(self) -> Share:
        return record(MESH)

    def rebuilt(self, mesh: dict[str, np.ndarray]) -> ChannelDiscretisation:
        return discretise(self.setup, mesh_from_arrays(**mesh))


def build_channel_column(config: Config) -> ChannelCollapse:
    """Netgen mesh of the column in its channel, the solver and the mover on it, the
    column at rest with its hydrostatic pressure, the loop, its remesher and measures."""
    setup = ChannelSetup.of(config)
    current = discretise(setup, extruded_mesh(setup.section, setup.span, setup.size))
    current.solver.set_state(ngs.CF((0.0, 0.0, 0.0)), _hydrostatic(setup, current.mesh))
    simulation = Simulation(solver=current.solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations,
                            mesh_motion=current.mover,
                            mesher_failures=LOFT_FAILURES,
                            velocity_floor=config.numerics.velocity_floor)
    remesher = ChannelRemesher(setup, current, simulation)
    simulation.remesher = remesher
    measures = ChannelMeasures(setup, current, remesher, simulation)
    add_callback(simulation, measures, "collapse")
    if config.time.stop_at_rest:
        simulation.stop_criteria = [RestCriterion(measures.flowing_fraction,
                                                  config.time.rest_fraction,
                                                  config.time.rest_duration)]
    return ChannelCollapse(setup, current, simulation, remesher, measures)


def _hydrostatic(setup: ChannelSetup, mesh: ngs.Mesh) -> ngs.GridFunction:
    """The pressure at rest, -rho g_z (depth below the section's surface), at the
    vertices."""
    g_z = setup.flow.terms.body_force[2]
    xyz = mesh.ngmesh.Coordinates()
    heights = np.array([setup.section.surface_height(x) for x in xyz[:, 0]])
    pressure = ngs.GridFunction(ngs.H1(mesh, order=1))
    pressure.vec.FV().NumPy()[:] = (-setup.config.material.density * g_z
                                    * np.maximum(heights - xyz[:, 2], 0.0))
    return pressure


register("column", build_channel_column, figures=ChannelMeasures.figures, dimension=3)
