"""Remeshing a 3D column: when its tetrahedra have degraded (or a move would invert one),
a new mesh of the moved body (``ale/channel_remesh.py``) and the state carried onto it
(``ale/transfer3d.py``: interpolation inside the old body, then a divergence-free
projection; the solver takes its own history across, ``FlowSolver.inherit``). It keeps
the remeshes' record: count, volume changes, quality."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar

from granflow.ale.channel_remesh import lofted_remesh
from granflow.ale.transfer import transfer_tensor, transfer_vertices
from granflow.ale.transfer3d import ChannelStateTransfer
from granflow.fem.coupling import Carriers
from granflow.fem.measure import SPACE
from granflow.geometry.mesh3d import tetrahedron_quality
from granflow.scenarios.channel_discretisation import ChannelDiscretisation, discretise
from granflow.scenarios.channel_setup import ChannelSetup
from granflow.simulation.simulation import Simulation
from granflow.state.spec import COUNT, REAL, Share, list_of, number


def _no_cells(old: Any, new: Any) -> None:
    """A piecewise-constant field (a packing's) has no 3D carrier: the rules refuse a
    packing in 3D (``three_d_rules.py``)."""
    raise NotImplementedError("a piecewise-constant field is not carried across a 3D remesh")


@dataclass
class ChannelRemesher:
    """The loop's ``Remesher`` for a 3D column (``simulation.py``)."""

    setup: ChannelSetup
    current: ChannelDiscretisation
    simulation: Simulation
    remeshes: int = 0
    fresh_quality: float = 1.0
    changes: list[float] = field(default_factory=list)    # relative volume, per remesh
    unrecorded_change: float = 0.0   # volume change of the remeshes since the last row
    share: ClassVar[Share] = {     # its share of a checkpoint (``save_state``)
        "remeshes": COUNT, "fresh_quality": number(0.0), "remesh_changes": list_of(REAL)}

    def __post_init__(self) -> None:
        self.fresh_quality = self.quality()

    def quality(self) -> float:
        """The worst tetrahedron's shape quality (``tetrahedron_quality``)."""
        return float(tetrahedron_quality(self.current.mesh).min())

    def needs_remesh(self) -> bool:
        """Worst tetrahedron below mesh.remesh_quality, or below half of what a fresh
        mesh of this body achieved (its thin front caps the quality any mesh reaches)."""
        floor = min(self.setup.config.mesh.remesh_quality, 0.5 * self.fresh_quality)
        return floor > 0 and self.quality() < floor

    def degraded(self) -> bool:
        """Worst tetrahedron below mesh.failure_remesh_quality: a failed nonlinear solve
        on this mesh is answered by a remesh before a smaller step."""
        floor = self.setup.config.mesh.failure_remesh_quality
        return floor > 0 and self.quality() < floor

    def remesh(self) -> None:
        """A new mesh of the moved body; (u, p) at t^n and t^{n-1} carried onto it."""
        setup, old = self.setup, self.current
        mesh = lofted_remesh(old.mesh, setup.span, setup.size)
        new = discretise(setup, mesh)
        change = (new.mover.volume() - old.mover.volume()) / old.mover.initial_volume
        transfer = ChannelStateTransfer(new.solver.space, setup.wall_labels(),
                                        setup.config.boundary.penalty, SPACE)
        new.solver.inherit(old.solver, Carriers(transfer.apply, transfer_tensor,
                                                transfer_vertices, _no_cells))
        new.mover.inherit(old.mover)
        self.changes.append(change)
        self.unrecorded_change += change
        self.current.replace(new)
        self.simulation.replace(new.solver, new.mover)
        self.remeshes += 1
        self.fresh_quality = self.quality()

    def recorded(self) -> None:
        """A diagnostics row has reported the volume change of the remeshes so far."""
        self.unrecorded_change = 0.0

    def summary(self) -> dict[str, Any]:
        return {"remeshes": self.remeshes,
                "remesh_volume_change_max": max(map(abs, self.changes), default=0.0)}

    def save_state(self) -> dict[str, Any]:
        return {"remeshes": self.remeshes, "fresh_quality": self.fresh_quality,
                "remesh_changes": list(self.changes)}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.remeshes, self.fresh_quality = state["remeshes"], state["fresh_quality"]
        self.changes = list(state["remesh_changes"])
