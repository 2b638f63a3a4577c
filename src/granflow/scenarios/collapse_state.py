"""A collapse's share of a checkpoint (``io/run_state.py``), one sequence for the section's
column (``column.py``) and the channel's (``channel_column.py``): the mesh as the problem
stores it, the flow's history, the mover, the remeshes' record, then the shares of the
loop's callbacks; restored by rebuilding the solver and the mover on the saved mesh and
handing them to the loop before the callbacks take their shares back."""

from __future__ import annotations

from typing import Any, ClassVar, Protocol

from granflow.simulation.simulation import Simulation
from granflow.state.spec import Share, record


class _Remesher(Protocol):
    share: ClassVar[Share]

    def save_state(self) -> dict[str, Any]: ...
    def restore_state(self, state: dict[str, Any]) -> None: ...


class CheckpointedCollapse:
    """``save_state``, ``share`` and ``restore_state`` of an assembled collapse, from its
    ``current`` discretisation (mesh, solver, mover; ``replace``), its ``remesher`` and its
    ``simulation``. A collapse says how its mesh is stored (``saved_mesh``, its share
    ``mesh_share``) and how a discretisation is rebuilt on a stored one (``rebuilt``)."""

    current: Any
    simulation: Simulation
    remesher: _Remesher

    def saved_mesh(self) -> Any:
        """The mesh as a checkpoint holds it."""
        raise NotImplementedError

    def mesh_share(self) -> Share | Any:
        """What ``saved_mesh`` may be in a checkpoint."""
        raise NotImplementedError

    def rebuilt(self, mesh: Any) -> Any:
        """A fresh discretisation (solver and mover) on the stored mesh ``mesh``."""
        raise NotImplementedError

    def save_state(self) -> dict[str, Any]:
        """The mesh (with its boundary labels, which deposition changes), the flow history,
        the mover and the remeshes' record, then the loop's callbacks' shares (the
        diagnostics history, a layer, a mobilisation state)."""
        return {"mesh": self.saved_mesh(), "fields": self.current.solver.save_history(),
                "mover": self.current.mover.save_state(), **self.remesher.save_state(),
                **self.simulation.callbacks.save_state()}

    def share(self) -> Share:
        """What the members of ``save_state`` may be (in a checkpoint): its parts' shares."""
        return {"mesh": self.mesh_share(),
                "fields": record(self.current.solver.history_share()),
                "mover": record(type(self.current.mover).share),
                **type(self.remesher).share, **self.simulation.callbacks.shares()}

    def restore_state(self, state: dict[str, Any]) -> None:
        """Continue from ``save_state``: solver and mover rebuilt on the saved mesh, then
        the callbacks' shares on them."""
        restored = self.rebuilt(state["mesh"])
        restored.solver.restore_history(state["fields"])
        restored.mover.restore_state(state["mover"])
        self.current.replace(restored)
        self.simulation.replace(restored.solver, restored.mover)
        self.remesher.restore_state(state)
        self.simulation.callbacks.restore_state(state)
