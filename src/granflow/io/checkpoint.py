"""Checkpoint files: the run's ``SimulationState`` pickled into ``checkpoint/state.pkl``.

Written atomically (temporary file, fsync, rename), so a run killed while writing leaves
the previous checkpoint intact. Pickle because the state holds an NGSolve mesh (which
pickles with its boundary labels and exact coordinates) and numpy arrays; a checkpoint is
read only by the granflow that wrote it, from the user's own run directory.
"""

from __future__ import annotations

import pickle
from pathlib import Path

from granflow.io.run_dir import RunDir
from granflow.simulation.state import STATE_VERSION, SimulationState

CHECKPOINT_FILE = "checkpoint/state.pkl"


class CheckpointError(Exception):
    """The run directory holds no usable checkpoint (the message says why)."""


def write_checkpoint(run_dir: RunDir, state: SimulationState) -> Path:
    return run_dir.write_bytes(CHECKPOINT_FILE, pickle.dumps(state, protocol=5))


def read_checkpoint(root: Path) -> SimulationState:
    path = Path(root) / CHECKPOINT_FILE
    if not path.is_file():
        raise CheckpointError(f"'{root}' holds no checkpoint ({CHECKPOINT_FILE}); a run "
                              "checkpoints every output.checkpoint_every steps, when it is "
                              "interrupted and when it fails")
    try:
        state = pickle.loads(path.read_bytes())
    except Exception as exc:  # a truncated or foreign file
        raise CheckpointError(f"cannot read the checkpoint '{path}': {exc}") from None
    if not isinstance(state, SimulationState) or state.version != STATE_VERSION:
        raise CheckpointError(f"the checkpoint '{path}' was written by another version of "
                              "granflow; rerun the case")
    return state
