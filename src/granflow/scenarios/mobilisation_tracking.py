"""The mobilisation state of a hysteretic friction through a run (``physics/hysteresis.py``):
advanced after each accepted step (carried with the material through the moving mesh, then
relaxed at the step's shear rates; ``fem/mobilisation_field.py``), carried through every remesh of
a collapse, and checkpointed. Used by the collapse and by the periodic layer (where the flow
runs along the bed and the state, uniform along it, needs nothing across the periodic ends:
the transport treats them as walls).

The step is applied once, whichever comes first after it is accepted: a remesh (before the
state moves to the new mesh, on the mesh the step was computed on) or this callback. The
stretch of erodible layer a remesh adds ahead of the flow (``mesh.layer_ahead``) has been at
rest since t = 0: its state is the layer's initial one relaxed for t at rest,
s0 exp(-t / tau_r).

Its outputs (``simulation/outputs.py``): the diagnostics column ``mobilised_fraction``, the
mean of s over the mass (area-weighted; in r-z over the volume of revolution); the cell data
``mobilisation`` of the VTU snapshots (s per triangle); its state in the checkpoint.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol

import ngsolve as ngs
import numpy as np

from granflow.ale.transfer import transfer_cells
from granflow.fem.flow import FlowSolver
from granflow.fem.mobilisation_field import MobilisationCoupling, MobilisationField
from granflow.fem.sampling import triangles
from granflow.physics.hysteresis import Relaxation, pick, relaxation, relaxed
from granflow.scenarios.materials import RunMaterials
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import Simulation
from granflow.state.spec import TIME, Share, array, assign, may_lack


class Host(Protocol):
    """Where the current mesh, flow and state live (a collapse's remesh replaces them)."""

    mesh: ngs.Mesh
    solver: FlowSolver
    mobilisation: MobilisationField | None


@dataclass
class MobilisationTracking(Outputs):
    """The loop's callback that owns the mobilisation's time (``t``: the state is s(t))."""

    columns = ("mobilised_fraction",)
    share: ClassVar[Share] = {"mobilisation": may_lack(array("cells")),   # restore says
                              "mobilisation_t": may_lack(TIME)}            # if missing

    materials: RunMaterials
    current: Host
    simulation: Simulation
    t: float = 0.0
    _coordinates: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._coordinates = self.current.mesh.ngmesh.Coordinates().copy()

    @property
    def field(self) -> MobilisationField:
        assert self.current.mobilisation is not None
        return self.current.mobilisation

    def _share(self, column: Any, layer: Any) -> Any:
        """A value per triangle: the column's, or the layer's where it holds most of it."""
        fraction = getattr(self.current, "fraction", None)
        if fraction is None:          # one material
            return column
        return pick(column, layer, fraction.vec.FV().NumPy())

    def relaxation(self) -> Relaxation:
        """The relaxation of each triangle's material."""
        column = relaxation(self.materials.column)
        if self.materials.layer is None:
            return column
        layer = relaxation(self.materials.layer)
        return Relaxation(*(self._share(getattr(column, k), getattr(layer, k))
                            for k in ("mobilisation_time", "rest_time", "shear_rate")))

    def start(self) -> None:
        """s at t = 0: each material's initial mobilisation (material at rest: 0)."""
        self.field.values[:] = self._share(self.materials.column.initial_mobilisation,
                                           self.materials.of_layer.initial_mobilisation)
        self.t = 0.0
        self._coordinates = self.current.mesh.ngmesh.Coordinates().copy()

    def advance(self) -> None:
        """Apply the accepted step not yet applied (if any) on the current mesh."""
        dt = self.simulation.t - self.t
        if dt <= 0:
            return
        solver, xy = self.current.solver, self.current.mesh.ngmesh.Coordinates()
        self.field.advect(solver.velocity, xy - self._coordinates, dt)
        rates = self.field.shear_rates(solver.strain_rate_norm())
        self.field.relax(self.relaxation(), rates, dt)
        self.t = self.simulation.t
        self._coordinates = xy.copy()

    def __call__(self, sim: Simulation) -> None:
        self.advance()

    def carry(self, new: Host, old_end: float) -> None:
        """Before a remesh replaces the current discretisation by ``new``: the pending step
        on the old mesh, then the state onto the new one; material beyond ``old_end`` (a
        lengthened layer) has been at rest from the start."""
        self.advance()
        assert new.mobilisation is not None
        transfer_cells(self.field.state, new.mobilisation.state)
        xy = new.mesh.ngmesh.Coordinates()
        added = xy[triangles(new.mesh)].mean(axis=1)[:, 0] > old_end
        if added.any():
            layer = self.materials.of_layer
            new.mobilisation.values[added] = relaxed(layer.initial_mobilisation, 0.0,
                                                     layer.rest_time, self.t)
        self._coordinates = xy.copy()

    def mobilised_fraction(self) -> float:
        """The mean of s over the mass (module docstring)."""
        solver = self.current.solver
        return solver.coordinates.integrate(self.field.state, self.current.mesh) / (
            solver.volume())

    # --- outputs ------------------------------------------------------------------------
    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        return {"mobilised_fraction": self.mobilised_fraction()}

    def fields(self) -> dict[str, np.ndarray]:
        return {"mobilisation": self.field.values.copy()}

    def save_state(self) -> dict[str, Any]:
        return {"mobilisation": self.field.values.copy(), "mobilisation_t": self.t}

    def restore_state(self, state: dict[str, Any]) -> None:
        """The state of a checkpoint, on the discretisation rebuilt on its mesh."""
        if "mobilisation" not in state:
            raise ValueError("this checkpoint was written without a hysteretic friction; "
                             "run the case again from the start")
        assign(self.field.values, state["mobilisation"], "the checkpoint's mobilisation")
        self.t = float(state["mobilisation_t"])
        self._coordinates = self.current.mesh.ngmesh.Coordinates().copy()


def mobilisation_of(solver: FlowSolver) -> MobilisationField | None:
    """A solver's hysteretic friction state, None without a hysteretic friction."""
    coupling = solver.coupling(MobilisationCoupling)
    return coupling.field if coupling is not None else None
