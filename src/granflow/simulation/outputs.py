"""What each part of a problem declares to the run's outputs, and ``simulation.callbacks``,
which the runner walks for each kind of output.

A part (a problem's own measures, the erodible layer, the mobilisation state of a
hysteretic friction...) subclasses ``Outputs``, overrides what it has and is added to the
simulation as a named callback (``callbacks.add_callback``). For every output the runner
asks all callbacks, in the order they were added, and never what the problem is: its
diagnostics columns and their values each step, its profiles at output times, its cell
data in the VTU snapshots, its animation frames, its summary members, its share of the
checkpoint, and (per class, for ``granflow plot``, which builds no problem) its figures.
Everything declared is plain data; the files are ``io/``'s.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, ClassVar

import numpy as np

from granflow.simulation.callbacks import Callback, Simulation
from granflow.simulation.outcomes import RunResult
from granflow.state.spec import Share

Table = tuple[list[str], np.ndarray]       # a profile: column names, rows
Figure = Callable[[Any, Any], None]        # (run_dir, config): drawn from the run's files


class Outputs:
    """A part's outputs; each member declares nothing unless overridden."""

    columns: ClassVar[tuple[str, ...]] = ()     # its diagnostics.csv columns
    figures: ClassVar[tuple[Figure, ...]] = ()  # figures of its files (none without them)
    animated: ClassVar[bool] = False            # it gives the animation's frames
    share: ClassVar[Share] = {}                 # its share of the checkpoint, member by member

    def __call__(self, sim: Simulation) -> None:
        """Its work after an accepted step (on its callback's schedule)."""

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        """This accepted step's values of its columns (``cell_speed``: mean |u| per
        triangle, computed once per step for all)."""
        return {}

    def record(self, row: dict[str, float]) -> None:
        """The step's whole diagnostics row, once written (a history for the summary)."""

    def profiles(self, t: float) -> dict[str, Table]:
        """Its profiles of the current state, written for output time ``t``."""
        return {}

    def fields(self) -> dict[str, np.ndarray]:
        """Its cell data (one value per triangle) for a VTU snapshot."""
        return {}

    def frame(self, sim: Simulation) -> dict[str, Any]:
        """An animation frame of the current state (``animated`` parts)."""
        return {}

    def summary(self, result: RunResult) -> dict[str, Any]:
        """Its summary.json members at the end of the run."""
        return {}

    def save_state(self) -> dict[str, Any]:
        """Its share of the checkpoint (plain data, each member declared in ``share``)."""
        return {}

    def restore_state(self, state: dict[str, Any]) -> None:
        """Continue from ``save_state`` (the problem's mesh and flow already restored)."""


class Callbacks(dict[str, Callback]):
    """``simulation.callbacks``: name -> ``Callback``, run in the order added; the walks
    below gather what their ``Outputs`` declare."""

    def parts(self) -> list[Outputs]:
        return [c.func for c in self.values() if isinstance(c.func, Outputs)]

    def columns(self) -> list[str]:
        return [name for part in self.parts() for name in part.columns]

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        row: dict[str, float] = {}
        for part in self.parts():
            row |= part.diagnostics(sim, cell_speed)
        return row

    def record(self, row: dict[str, float]) -> None:
        for part in self.parts():
            part.record(row)

    def profiles(self, t: float) -> dict[str, Table]:
        out: dict[str, Table] = {}
        for part in self.parts():
            out |= part.profiles(t)
        return out

    def fields(self) -> dict[str, np.ndarray]:
        out: dict[str, np.ndarray] = {}
        for part in self.parts():
            out |= part.fields()
        return out

    def frame_source(self) -> Outputs | None:
        """The part that gives the animation's frames (None: no animation)."""
        return next((part for part in self.parts() if part.animated), None)

    def summary(self, result: RunResult) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for part in self.parts():
            out |= part.summary(result)
        return out

    def save_state(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for part in self.parts():
            out |= part.save_state()
        return out

    def shares(self) -> Share:
        """What the members of their shares of the checkpoint may be."""
        out: dict[str, Any] = {}
        for part in self.parts():
            out |= part.share
        return out

    def restore_state(self, state: dict[str, Any]) -> None:
        for part in self.parts():
            part.restore_state(state)
