"""A 3D column discretised on one mesh: the flow solver (3.2) of the set-up's frozen parts,
on one process or distributed over MPI ranks (``fem/distributed_flow.py``), and the ALE
mover (3.6)/(3.7) in the volume (``ale/channel_mover.py``). A remesh builds a new one; the
parts that read the current mesh hold the same ``ChannelDiscretisation`` object."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import ngsolve as ngs

from granflow.ale.channel_mover import ChannelMover
from granflow.ale.mesh_motion import ElasticMeshVelocity, LagrangeMeshVelocity
from granflow.fem.distributed_flow import flow_solver
from granflow.scenarios.channel_setup import ChannelSetup


@dataclass
class ChannelDiscretisation:
    """The current mesh and what lives on it."""

    mesh: ngs.Mesh
    solver: Any                      # FlowSolver, or its distributed stand-in
    mover: ChannelMover

    def replace(self, other: ChannelDiscretisation) -> None:
        """Take ``other``'s mesh, solver and mover (after a remesh or a restore)."""
        self.mesh, self.solver, self.mover = other.mesh, other.solver, other.mover


def discretise(setup: ChannelSetup, mesh: ngs.Mesh) -> ChannelDiscretisation:
    """The flow solver (3.2) and the ALE mover (3.6)/(3.7) on ``mesh``."""
    num = setup.config.numerics
    solver = flow_solver(mesh, setup.flow)
    velocity_cls = LagrangeMeshVelocity if num.mesh_velocity == "lagrange" else (
        ElasticMeshVelocity)
    source = ngs.GridFunction(solver.space.components[0])
    w_solver = velocity_cls(mesh, source, solver.mesh_velocity, num.mesh_penalty)
    mover = ChannelMover(mesh, w_solver, source=source, flow=solver,
                         target=solver.mesh_velocity, span=setup.span,
                         extrapolate=num.ale_extrapolation,
                         conserve_volume=num.volume_correction)
    return ChannelDiscretisation(mesh, solver, mover)
