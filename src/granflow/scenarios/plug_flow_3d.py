"""The periodic layer of configuration (a) in three dimensions: a box periodic along the
slope (X) and across it (Y), the rough bed at Z = 0 and the free surface at Z = height
(paper section 4). The flow is the 2D layer's, uniform in X and Y: its velocity against
the 1D solver of (4.1) is the first verification of the 3D discretisation. Under
``mpiexec -n N`` rank 0 meshes and NGSolve distributes the mesh (``fem/mpi.py``); the
Taylor-Hood system is then gathered and factorised on rank 0."""

from __future__ import annotations

from dataclasses import replace

import ngsolve as ngs

from granflow.config import Config
from granflow.fem.flow_factory import build_flow
from granflow.fem.linalg import MASTER_INVERSE, distributed
from granflow.fem.measure import SPACE
from granflow.fem.mpi import distribute
from granflow.geometry.labels import BED
from granflow.geometry.mesh3d import periodic_box_mesh
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.materials import run_materials
from granflow.scenarios.plug_flow import PlugFlow
from granflow.simulation.simulation import Simulation
from granflow.simulation.timestep import step_policy

LAWS_3D = ("drucker-prager",)   # the laws verified in 3D so far (mu(I) next)


def build_plug_flow_3d(config: Config, width: float | None = None) -> PlugFlow:
    """Mesh, initial state U0 = (alpha1 [Z - b0]_+, 0, 0) with hydrostatic pressure, and
    the loop, on a box ``geometry.length`` long and ``width`` (default: as long) wide."""
    geo, mat = config.geometry, config.material
    if mat.rheology not in LAWS_3D or mat.friction != "constant":
        raise ValueError(f"material.rheology = {mat.rheology!r} (friction {mat.friction!r}) "
                         f"is not verified in 3D: use one of {', '.join(LAWS_3D)}")
    if config.numerics.method != "regularized" or config.numerics.mesh_velocity != "fixed":
        raise ValueError("the 3D layer runs the regularised law (2.13) on a fixed mesh: "
                         "numerics.method = 'regularized', numerics.mesh_velocity = 'fixed'")
    mesh = distribute(lambda: periodic_box_mesh(geo.length, width or geo.length, geo.height,
                                                config.mesh.size))
    spec = flow_spec(config, run_materials(config),
                     Layout(SPACE, periodic=True, dirichlet=BED, rough=BED))
    if distributed(mesh):        # the system gathered and factorised on rank 0
        spec = replace(spec, solver=replace(spec.solver, linear_solver=MASTER_INVERSE))
    solver = build_flow(mesh, spec)
    force = spec.terms.body_force
    z = SPACE.bed_normal
    alpha, base = config.initial.shear_rate, config.initial.plug_base
    solver.set_state(ngs.CF((ngs.IfPos(z - base, alpha * (z - base), 0.0), 0.0, 0.0)),
                     -mat.density * force[2] * (geo.height - z))          # hydrostatic p
    simulation = Simulation(solver=solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations,
                            velocity_floor=config.numerics.velocity_floor)
    return PlugFlow(config=config, mesh=mesh, solver=solver, simulation=simulation)
