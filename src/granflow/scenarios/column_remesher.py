"""Remeshing the collapse: when the mesh has degraded, a new mesh of the same boundary
(``ale/remesh.py``) and the state carried onto it (``ale/transfer.py``: interpolation inside
the old domain, then a divergence-free projection; the solver takes its own history across,
``FlowSolver.inherit``). It also keeps the remeshes' record: count, area changes, quality.

With ``mesh.layer_ahead`` > 0 an erodible layer is meshed only that far ahead of the moving
material; when moving material comes within half of it of the layer's end, the remesh
lengthens the layer (``ale/remesh.lengthen_layer``). The stretch added was at rest behind the
frictionless end wall, so its state is the one the transfer gives it: the velocity at the old
end (about 0) and the hydrostatic pressure at the same depth."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from granflow.ale.mesh_motion import vertex_values
from granflow.ale.remesh import remesh, shape_quality
from granflow.ale.size_field import SizeField
from granflow.ale.transfer import (
    StateTransfer,
    transfer_cells,
    transfer_tensor,
    transfer_vertices,
)
from granflow.diagnostics.state import FLOWING_SPEED
from granflow.fem.coupling import Carriers
from granflow.geometry.stretch import LayerStretch
from granflow.scenarios.column_discretisation import (
    ColumnDiscretisation,
    discretise,
    friction_walls,
)
from granflow.scenarios.column_layer import LayerTracking
from granflow.scenarios.column_setup import ColumnSetup
from granflow.scenarios.column_sizes import refit_due, refitted, remesh_sizes
from granflow.scenarios.mobilisation_tracking import MobilisationTracking
from granflow.simulation.simulation import Simulation
from granflow.state.spec import (
    COUNT,
    FLAG,
    REAL,
    Share,
    array,
    list_of,
    may_lack,
    number,
    record,
    tuple_of,
)

SIZE_FIELD: Share = {   # ``SizeField.state``: the layer's windows and the moving points
    "windows": array(None, 2), "moving": array(None, 2), "bulk_fine_everywhere": FLAG}


@dataclass
class ColumnRemesher:
    """The loop's ``Remesher`` for a column (``simulation.py``)."""

    setup: ColumnSetup
    current: ColumnDiscretisation
    simulation: Simulation
    remeshes: int = 0
    fresh_quality: float = 1.0
    changes: list[float] = field(default_factory=list)    # relative area, per remesh
    restored: list[float] = field(default_factory=list)   # area its simplification lost
    unrecorded_change: float = 0.0   # area change of the remeshes since the last diagnostics row
    layer: LayerTracking | None = None   # an erodible layer's tracked material
    mobilisation: MobilisationTracking | None = None   # a hysteretic friction's state
    lengthenings: int = 0          # times the meshed layer was lengthened (mesh.layer_ahead)
    added: float = 0.0             # the layer area (r-z: volume) they added
    size_field: SizeField | None = None   # mesh.adaptive: the sizes the mesh was made with
    refits: int = 0                # remeshes because the mesh no longer fit the flow
    share: ClassVar[Share] = {     # its share of a checkpoint (``save_state``)
        "remeshes": COUNT, "fresh_quality": number(0.0), "remesh_changes": list_of(REAL),
        "remesh_restored": list_of(REAL), "layer_lengthened": may_lack(tuple_of(COUNT, REAL)),
        "size_field": may_lack(record(SIZE_FIELD)), "refits": may_lack(COUNT)}

    @property
    def stretch(self) -> LayerStretch:
        """The layer's stretched cells (``geometry/stretch.py``): kept by every remesh, and
        the coordinates in which the mesh's quality is measured."""
        return self.setup.stretch

    def needs_remesh(self) -> bool:
        """Worst triangle below mesh.remesh_quality, or below half of what a fresh mesh of
        this domain achieved (a sharp front tip caps the quality any mesh can reach); or a
        bed edge across a corner of the bed profile (the corner made a vertex again)."""
        floor = min(self.setup.config.mesh.remesh_quality, 0.5 * self.fresh_quality)
        degraded = floor > 0 and float(shape_quality(self.current.mesh, self.stretch).min()) < floor
        return (degraded or self.layer_end_due() is not None
                or self.current.mover.straddles_corner() or self.refit_due())

    def refit_due(self) -> bool:
        """An adaptive mesh no longer fits the flow: it has come within half of
        mesh.flow_margin of coarse cells, or left much of the fine mesh at rest
        (``column_sizes.refit_due``)."""
        return self.size_field is not None and refit_due(self.setup, self.current,
                                                         self.size_field)

    def layer_end_due(self) -> float | None:
        """The meshed layer's new end when material faster than the flowing threshold has
        come within half of mesh.layer_ahead of its end (else None)."""
        ahead, mover = self.setup.config.mesh.layer_ahead, self.current.mover
        if ahead <= 0 or mover.end_x >= self.setup.config.geometry.bed_length:
            return None
        mesh = self.current.mesh     # u^n at the vertices: its P2 vertex coefficients
        speed = np.linalg.norm(vertex_values(self.current.solver.previous.components[0]),
                               axis=1)
        moving = speed > FLOWING_SPEED
        furthest = float(mesh.ngmesh.Coordinates()[moving, 0].max()) if moving.any() else 0.0
        if furthest < mover.end_x - 0.5 * ahead:
            return None
        return self.setup.layer_end(furthest)

    def degraded(self) -> bool:
        """Worst triangle below mesh.failure_remesh_quality: a failed nonlinear solve on
        this mesh is answered by a remesh before a smaller step."""
        floor = self.setup.config.mesh.failure_remesh_quality
        return floor > 0 and float(shape_quality(self.current.mesh, self.stretch).min()) < floor

    def remesh(self) -> None:
        """New mesh of the same boundary; (u, p) at t^n and t^{n-1} transferred onto it."""
        old = ColumnDiscretisation(self.current.mesh, self.current.solver, self.current.mover)
        end = self.layer_end_due()
        setup = self.setup
        sizes: dict = {"edge_size": setup.layer_edge_sizes()}
        if self.size_field is not None:      # refitted to the flow at t^n
            self.refits += self.refit_due()
            self.size_field = refitted(setup, old, self.size_field,
                                       old.mover.end_x if end is None else end)
            sizes = remesh_sizes(setup, self.size_field)
        remeshed = remesh(old.mesh, setup.config.mesh.size, measure=old.mover.measure,
                          layer_end=end, layer_top=setup.config.geometry.erodible_thickness,
                          stretch=self.stretch, bed=old.mover.support.bed,
                          cut=old.mover.fold_pocket, **sizes)
        new = discretise(setup, remeshed.mesh,
                         self.layer.material if self.layer is not None else None)
        added = remeshed.area_added
        change = (new.mover.area() - old.mover.area() - added) / old.mover.initial_area
        self.changes.append(change)
        self.restored.append(remeshed.area_restored)
        self.unrecorded_change += change
        transfer = StateTransfer(new.solver.space, friction_walls(setup),
                                 setup.config.boundary.penalty, new.solver.coordinates)
        new.solver.inherit(old.solver, Carriers(transfer.apply, transfer_tensor,
                                                transfer_vertices, transfer_cells))
        new.mover.inherit(old.mover)
        if added:                         # the free-surface fix conserves the longer layer
            new.mover.initial_area += added
            self.lengthenings += 1
            self.added += added
        if self.mobilisation is not None:
            self.mobilisation.carry(new, old.mover.end_x)
        self.current.replace(new)
        self.simulation.replace(new.solver, new.mover)
        self.remeshes += 1
        self.fresh_quality = float(shape_quality(new.mesh, self.stretch).min())

    def recorded(self) -> None:
        """A diagnostics row has reported the area change of the remeshes so far."""
        self.unrecorded_change = 0.0

    def summary(self) -> dict[str, Any]:
        out = {"remeshes": self.remeshes,
               "remesh_area_change_max": max(map(abs, self.changes), default=0.0),
               "remesh_area_restored_max": max(map(abs, self.restored), default=0.0)}
        if self.setup.config.mesh.layer_ahead > 0 and self.setup.erodible:
            out |= {"layer_lengthenings": self.lengthenings, "layer_added": self.added,
                    "layer_meshed_end_m": self.current.mover.end_x}
        if self.size_field is not None:
            out["adaptive_refits"] = self.refits
        return out

    def save_state(self) -> dict[str, Any]:
        return {"remeshes": self.remeshes, "fresh_quality": self.fresh_quality,
                "remesh_changes": list(self.changes), "remesh_restored": list(self.restored),
                "layer_lengthened": [self.lengthenings, self.added],
                **({} if self.size_field is None else {
                    "size_field": self.size_field.state(), "refits": self.refits})}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.remeshes, self.fresh_quality = state["remeshes"], state["fresh_quality"]
        self.changes = list(state["remesh_changes"])
        self.restored = list(state["remesh_restored"])
        count, added = state.get("layer_lengthened", (0, 0.0))
        self.lengthenings, self.added = int(count), float(added)
        if self.size_field is not None and "size_field" in state:
            self.size_field = self.size_field.from_state(state["size_field"])
            self.refits = int(state["refits"])
