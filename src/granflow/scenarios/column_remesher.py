"""Remeshing the collapse: when the mesh has degraded, a new mesh of the same boundary
(``ale/remesh.py``) and the state carried onto it (``ale/transfer.py``: interpolation inside
the old domain, then a divergence-free projection; the solver takes its own history across,
``FlowSolver.inherit``). It also keeps the remeshes' record: count, area changes, quality."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from granflow.ale.remesh import remesh, shape_quality
from granflow.ale.transfer import StateTransfer, transfer_tensor
from granflow.config import Config
from granflow.scenarios.column_discretisation import (
    ColumnDiscretisation,
    discretise,
    friction_walls,
    layer_edge_sizes,
)
from granflow.scenarios.column_layer import LayerTracking
from granflow.simulation.simulation import Simulation


@dataclass
class ColumnRemesher:
    """The loop's ``Remesher`` for a column (``simulation.py``)."""

    config: Config
    current: ColumnDiscretisation
    simulation: Simulation
    remeshes: int = 0
    fresh_quality: float = 1.0
    changes: list[float] = field(default_factory=list)    # relative area, per remesh
    restored: list[float] = field(default_factory=list)   # area its simplification lost
    unrecorded_change: float = 0.0   # area change of the remeshes since the last diagnostics row
    layer: LayerTracking | None = None   # an erodible layer's tracked material

    def needs_remesh(self) -> bool:
        """Worst triangle below mesh.remesh_quality, or below half of what a fresh mesh of
        this domain achieved (a sharp front tip caps the quality any mesh can reach)."""
        floor = min(self.config.mesh.remesh_quality, 0.5 * self.fresh_quality)
        return floor > 0 and float(shape_quality(self.current.mesh).min()) < floor

    def degraded(self) -> bool:
        """Worst triangle below mesh.failure_remesh_quality: a failed nonlinear solve on
        this mesh is answered by a remesh before a smaller step."""
        floor = self.config.mesh.failure_remesh_quality
        return floor > 0 and float(shape_quality(self.current.mesh).min()) < floor

    def remesh(self) -> None:
        """New mesh of the same boundary; (u, p) at t^n and t^{n-1} transferred onto it."""
        old = ColumnDiscretisation(self.current.mesh, self.current.solver, self.current.mover)
        remeshed = remesh(old.mesh, self.config.mesh.size, layer_edge_sizes(self.config),
                          old.mover.measure)
        new = discretise(self.config, remeshed.mesh,
                         self.layer.material if self.layer is not None else None)
        change = (new.mover.area() - old.mover.area()) / old.mover.initial_area
        self.changes.append(change)
        self.restored.append(remeshed.area_restored)
        self.unrecorded_change += change
        transfer = StateTransfer(new.solver.space, friction_walls(self.config),
                                 self.config.boundary.penalty, new.solver.coordinates)
        new.solver.inherit(old.solver, transfer.apply, transfer_tensor)
        new.mover.inherit(old.mover)
        self.current.replace(new)
        self.simulation.replace(new.solver, new.mover)
        self.remeshes += 1
        self.fresh_quality = float(shape_quality(new.mesh).min())

    def recorded(self) -> None:
        """A diagnostics row has reported the area change of the remeshes so far."""
        self.unrecorded_change = 0.0

    def summary(self) -> dict[str, Any]:
        return {"remeshes": self.remeshes,
                "remesh_area_change_max": max(map(abs, self.changes), default=0.0),
                "remesh_area_restored_max": max(map(abs, self.restored), default=0.0)}

    def save_state(self) -> dict[str, Any]:
        return {"remeshes": self.remeshes, "fresh_quality": self.fresh_quality,
                "remesh_changes": list(self.changes), "remesh_restored": list(self.restored)}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.remeshes, self.fresh_quality = state["remeshes"], state["fresh_quality"]
        self.changes = list(state["remesh_changes"])
        self.restored = list(state["remesh_restored"])
