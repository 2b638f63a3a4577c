"""The state of a run in one explicit object, so that resuming is a load, not a replay.

A run's state is spread over the parts that own it: the loop (time, step, counters, the
step policy, the stop criteria), the scenario (its mesh with the boundary labels that
deposition changed, the flow history u^n, u^{n-1}, the mover's reference area and
counters, the surface-tension switch, the diagnostics history and animation frames) and
the runner (pending output times, the VTK index, the rows of diagnostics.csv). Each part
gives its share as plain data and takes it back; this class gathers the three shares.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

STATE_VERSION = 3   # bump when the layout changes; older checkpoints are then refused
                    # (1: the pickled checkpoints of granflow 0.1, never read; 2: the mesh
                    # in Netgen's text format, still read; 3: the mesh as arrays)


@dataclass
class SimulationState:
    """Everything a resumed run needs (checkpoint/state.npz, written by io/checkpoint.py)."""

    loop: dict[str, Any]       # Simulation.save_state(): t, dt, counters, policy, criteria
    scenario: dict[str, Any]   # the problem's save_state(): mesh, fields, mover, history
    outputs: dict[str, Any]    # the runner's: output times left, VTK index, csv rows
    version: int = STATE_VERSION

    @property
    def t(self) -> float:
        return float(self.loop["t"])

    @property
    def step(self) -> int:
        return int(self.loop["step"])
