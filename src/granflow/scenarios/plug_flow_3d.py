"""The periodic layer of configuration (a) in three dimensions: a box periodic along the
slope (X) and across it (Y), the rough bed at Z = 0 and the free surface at Z = height
(paper section 4). The flow is the 2D layer's, uniform in X and Y: its velocity against
the 1D solver of (4.1) is the first verification of the 3D discretisation. Under
``mpiexec -n N`` its solve is distributed over the ranks (``fem/distributed_flow.py``)."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.config import Config
from granflow.fem.distributed_flow import flow_solver
from granflow.fem.measure import SPACE
from granflow.geometry.labels import BED
from granflow.geometry.mesh3d import periodic_box_mesh
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.materials import run_materials
from granflow.scenarios.plug_flow import PlugFlow, PlugFlowOutputs
from granflow.scenarios.registry import register
from granflow.simulation.callbacks import add_callback
from granflow.simulation.simulation import Simulation
from granflow.simulation.timestep import step_policy


class PlugFlow3D(PlugFlow):
    """The 3D layer: as the 2D one, its velocity profile along the vertical through the
    middle of the box (u_x and u_z; u_y stays at round-off)."""

    def profile(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        geo = self.config.geometry
        z = np.linspace(0.0, geo.height, 481)
        z[-1] -= 1e-9  # stay inside the mesh
        u = vertical_profile_3d(self.mesh, self.solver.velocity, geo.length / 2,
                                geo.length / 2, z)
        ref = self.reference(t)
        return z, u[:, [0, 2]], ref(z) if ref is not None else np.full(len(z), np.nan)


def vertical_profile_3d(mesh: ngs.Mesh, velocity: ngs.CoefficientFunction, x: float,
                        y: float, z: np.ndarray) -> np.ndarray:
    """(len(z), 3) velocity samples along the vertical through (x, y)."""
    mesh.ngmesh.Update()  # the point-search tree must follow the moved vertices
    return np.array([velocity(mesh(x, y, float(zi))) for zi in z]).reshape(len(z), 3)


def build_plug_flow_3d(config: Config) -> PlugFlow3D:
    """Mesh (a box ``geometry.length`` long and as wide), initial state
    U0 = (alpha1 [Z - b0]_+, 0, 0) with hydrostatic pressure, the loop and its outputs.
    What a 3D layer may run is checked with the configuration (``three_d_rules``)."""
    geo, mat = config.geometry, config.material
    mesh = periodic_box_mesh(geo.length, geo.length, geo.height, config.mesh.size)
    spec = flow_spec(config, run_materials(config),
                     Layout(SPACE, periodic=True, dirichlet=BED, rough=BED))
    solver = flow_solver(mesh, spec)          # its solve distributed under mpiexec
    force = spec.terms.body_force
    z = SPACE.bed_normal
    alpha, base = config.initial.shear_rate, config.initial.plug_base
    solver.set_state(ngs.CF((ngs.IfPos(z - base, alpha * (z - base), 0.0), 0.0, 0.0)),
                     -mat.density * force[2] * (geo.height - z))          # hydrostatic p
    simulation = Simulation(solver=solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations,
                            velocity_floor=config.numerics.velocity_floor)
    problem = PlugFlow3D(config=config, mesh=mesh, solver=solver, simulation=simulation)
    add_callback(simulation, PlugFlowOutputs(problem), "plug_flow")
    return problem


register("periodic-layer", build_plug_flow_3d, figures=PlugFlowOutputs.figures, dimension=3)
