"""Periodic layer on an incline: the plug flow (configuration (a), paper section 4) and the
steady flow of a layer steeper than its friction (Drucker-Prager or mu(I)); the builder,
registered as the problem kind "periodic-layer", and its outputs (``PlugFlowOutputs``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.ale.mesh_motion import AleMover, VerticalMeshVelocity
from granflow.config import Config
from granflow.diagnostics.plug_flow import velocity_errors_l2, vertical_profile
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.flow import FlowSolver
from granflow.fem.flow_factory import build_flow
from granflow.fem.linalg import direct_solver
from granflow.fem.mobilisation_field import MobilisationField
from granflow.geometry.mesh import BED, periodic_layer_mesh
from granflow.physics import gravity_vector
from granflow.physics.nonlocal_fluidity import NonlocalFluidity
from granflow.reference.incline import SteadyProfile
from granflow.reference.periodic_layer import Reference, layer_reference, steep
from granflow.reference.plug1d import Plug1DSolution
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.fluidity import FluidityOutputs
from granflow.scenarios.materials import run_materials
from granflow.scenarios.mobilisation_tracking import MobilisationTracking, mobilisation_of
from granflow.scenarios.packing import PackingOutputs
from granflow.scenarios.registry import register
from granflow.simulation.callbacks import add_callback
from granflow.simulation.outputs import Outputs, Table
from granflow.simulation.simulation import RunResult, Simulation
from granflow.simulation.timestep import step_policy
from granflow.state.spec import Share, array, assign, record


@dataclass
class PlugFlow:
    """The assembled plug-flow problem: mesh, solver, time loop and its outputs."""

    config: Config
    mesh: ngs.Mesh
    solver: FlowSolver
    simulation: Simulation
    _references: dict[float, Plug1DSolution | SteadyProfile] = field(default_factory=dict)
    _found: Reference | str | None = None
    tracking: MobilisationTracking | None = None      # a hysteretic friction's callback

    @property
    def mobilisation(self) -> MobilisationField | None:
        """A hysteretic friction's state (else None)."""
        return mobilisation_of(self.solver)

    @property
    def steep(self) -> bool:
        """Slope steeper than the friction angle: no plug, the layer shears throughout."""
        return steep(self.config)

    def _layer_reference(self) -> Reference | str:
        """The law's reference of this layer, or why none applies
        (``reference/periodic_layer.py``), decided once."""
        if self._found is None:
            self._found = layer_reference(self.config)
        return self._found

    def reference_note(self) -> str | None:
        """Why no reference applies (one line), or None."""
        found = self._layer_reference()
        return found if isinstance(found, str) else None

    @property
    def reference_kind(self) -> str | None:
        """"1d" (the transient solution of (4.1)), "steady" (the steep layer's limit)."""
        found = self._layer_reference()
        return None if isinstance(found, str) else found.kind

    def reference(self, t: float) -> Plug1DSolution | SteadyProfile | None:
        """The independent reference at time t (cached); None if none applies."""
        found = self._layer_reference()
        if isinstance(found, str):
            return None
        key = -1.0 if found.kind == "steady" else round(t, 12)
        if key not in self._references:
            self._references[key] = found.at(t)
        return self._references[key]

    def velocity_errors(self, t: float) -> tuple[float, float | None] | None:
        """(absolute, relative) L2 errors against the reference at t, None without one."""
        ref = self.reference(t)
        if ref is None:
            return None
        # the voxel table of velocity_errors_l2 is uniform: resample on as many points
        # (the identity for the uniform grid of the 1D solver)
        z = np.linspace(ref.z[0], ref.z[-1], len(ref.z))
        return velocity_errors_l2(self.mesh, self.solver.velocity, z, ref(z))

    def velocity_error(self, t: float) -> float:
        """Relative L2 error e_L2(u) (Tables 1-2); NaN without a reference or when it is 0."""
        errors = self.velocity_errors(t)
        return math.nan if errors is None or errors[1] is None else errors[1]

    def save_state(self) -> dict[str, Any]:
        """The flow history and the vertex positions (the vertical mesh motion moves them;
        the periodic mesh's topology never changes), then the shares of the loop's
        callbacks (a mobilisation state)."""
        return {"fields": self.solver.save_history(),
                "coordinates": self.mesh.ngmesh.Coordinates().copy(),
                **self.simulation.callbacks.save_state()}

    def share(self) -> Share:
        """What the members of ``save_state`` may be (in a checkpoint): its parts' shares."""
        return {"fields": record(self.solver.history_share()),
                "coordinates": array(self.mesh.nv, self.mesh.dim),
                **self.simulation.callbacks.shares()}

    def restore_state(self, state: dict[str, Any]) -> None:
        assign(self.mesh.ngmesh.Coordinates(), state["coordinates"], "the saved vertices")
        self.solver.restore_history(state["fields"])
        self.simulation.callbacks.restore_state(state)

    def profile(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Z, the 2D velocity along the mid vertical and the 1D reference, at time t."""
        z = np.linspace(0.0, self.config.geometry.height, 481)
        z[-1] -= 1e-9  # stay inside the mesh
        u = vertical_profile(self.mesh, self.solver.velocity, self.config.geometry.length / 2, z)
        ref = self.reference(t)
        return z, u, ref(z) if ref is not None else np.full(len(z), np.nan)


def initial_fluidity(law: NonlocalFluidity, config: Config) -> ngs.CoefficientFunction:
    """g at t = 0: initial.fluidity times the local law's fluidity at the stress ratio
    tan(slope) of the layer at rest (hydrostatic p; 0 where tan(slope) <= mu_s)."""
    geo, mat = config.geometry, config.material
    force = gravity_vector(mat.gravity, geo.slope_deg)
    pressure = -mat.density * force[1] * (geo.height - ngs.y)
    mu = math.tan(math.radians(geo.slope_deg))
    if mu <= law.mu_s:
        return ngs.CF(0.0)
    local = (law.root_pressure(pressure, NGSOLVE_OPS) * (mu - law.mu_s)
             / (law.b * mu * law.grain_diameter))
    return config.initial.fluidity * local


def plug_flow_figure(run_dir: Any, config: Config) -> None:
    """The velocity profile against its reference (``io/plots.py``)."""
    from granflow.io.plots import plot_plug_flow

    plot_plug_flow(run_dir, config)


@dataclass
class PlugFlowOutputs(Outputs):
    """The periodic layer's outputs: the velocity along the mid vertical against its
    reference at the output times, the errors against it in the summary, the figure."""

    problem: PlugFlow
    figures = (plug_flow_figure,)

    def profiles(self, t: float) -> dict[str, Table]:
        """The velocity along the mid vertical and the reference at time ``t``, as
        ``io/profiles.py`` writes them."""
        z, u, ref = self.problem.profile(t)
        return {"velocity": (["z", "u_x", "u_z", "u_reference"], np.column_stack([z, u, ref]))}

    def summary(self, result: RunResult) -> dict[str, Any]:
        problem = self.problem
        ref = problem.reference(result.t_final) if result.t_final > 0 else None
        errors = problem.velocity_errors(result.t_final) if ref is not None else None
        return {
            "velocity_relative_error_l2": errors[1] if errors else None,
            "velocity_error_l2": errors[0] if errors else None,
            "reference_interface_m": ref.interface if ref else None,
            "reference": problem.reference_kind,
            "reference_note": problem.reference_note(),
        }


def build_plug_flow(config: Config) -> PlugFlow:
    """Mesh, initial state U0 = alpha1 [Z - b0]_+ with hydrostatic pressure, and the loop."""
    geo, mat = config.geometry, config.material
    mesh = periodic_layer_mesh(geo.length, geo.height, config.mesh.size, config.mesh.cells_x)
    force = gravity_vector(mat.gravity, geo.slope_deg)
    layout = Layout(periodic=True, dirichlet=BED, rough=BED,   # the bed is rough
                    initial_fluidity=initial_fluidity)
    solver = build_flow(mesh, flow_spec(config, run_materials(config), layout))
    z = ngs.y
    alpha, base = config.initial.shear_rate, config.initial.plug_base
    solver.set_state(ngs.CF((ngs.IfPos(z - base, alpha * (z - base), 0.0), 0.0)),
                     -mat.density * force[1] * (geo.height - z))          # hydrostatic p
    motion = None
    if config.numerics.mesh_velocity == "vertical":
        source = ngs.GridFunction(solver.space.components[0])
        w_solver = VerticalMeshVelocity(mesh, source, solver.mesh_velocity,
                                        penalty=config.numerics.mesh_penalty,
                                        solver=direct_solver(config.numerics.linear_solver))
        motion = AleMover(mesh, w_solver, source=source, flow=solver,
                          target=solver.mesh_velocity,
                          extrapolate=config.numerics.ale_extrapolation)
    simulation = Simulation(solver=solver, steps_policy=step_policy(config),
                            t_end=config.time.t_end,
                            max_iterations=config.numerics.max_iterations, mesh_motion=motion,
                            velocity_floor=config.numerics.velocity_floor)
    problem = PlugFlow(config=config, mesh=mesh, solver=solver, simulation=simulation)
    add_callback(simulation, PlugFlowOutputs(problem), "plug_flow")
    fluidity, packing = FluidityOutputs.of(problem), PackingOutputs.of(problem)
    for name, part in (("fluidity", fluidity), ("packing", packing)):
        if part is not None:
            add_callback(simulation, part, name)
    if problem.mobilisation is not None:
        problem.tracking = MobilisationTracking(run_materials(config), problem,
                                                simulation)
        problem.tracking.start()
        add_callback(simulation, problem.tracking, "mobilisation")
    return problem


register("periodic-layer", build_plug_flow, figures=PlugFlowOutputs.figures)
