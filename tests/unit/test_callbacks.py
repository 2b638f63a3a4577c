"""The loop's named callbacks (``simulation/callbacks.py``) and what a part declares to the
outputs through them (``simulation/outputs.py``), on a loop without a finite-element
engine: when each schedule runs its callback, in which order, and how the runner's walks
gather the parts' declarations."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from granflow.simulation.callbacks import (
    AtTimes,
    Callback,
    EveryNSteps,
    TimeInterval,
    add_callback,
)
from granflow.simulation.outcomes import IterationReport
from granflow.simulation.outputs import Outputs
from granflow.simulation.simulation import Simulation
from granflow.simulation.timestep import fixed_step


class Decay:
    """u' = -u by implicit Euler: the least a FlowStep is."""

    def __init__(self) -> None:
        self.u = self.trial = 1.0

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        self.trial = self.u / (1.0 + dt)
        return IterationReport(converged=True, iterations=1, relative_change=0.0)

    def local_error(self, dt: float) -> None:
        return None

    def accept(self, dt: float | None = None) -> None:
        self.u = self.trial

    def reject(self) -> None:
        self.trial = self.u


def loop(steps: int = 10, dt: float = 0.1) -> Simulation:
    return Simulation(solver=Decay(), steps_policy=fixed_step(dt, dt, 1e-6),
                      t_end=steps * dt, max_iterations=5)


def test_each_schedule_runs_its_callback_when_due_in_the_order_added() -> None:
    sim = loop()                                   # 10 steps of 0.1 s
    seen: list[tuple[str, int]] = []
    reached: list[float] = []

    def note(name: str) -> Any:
        return lambda s: seen.append((name, s.step))

    at = AtTimes([0.25, 0.5, 5.0])
    add_callback(sim, note("every"), "every")
    add_callback(sim, Callback(note("third"), EveryNSteps(3)), "third")
    add_callback(sim, note("interval"), "interval", schedule=TimeInterval(0.35))
    add_callback(sim, lambda s: reached.extend(at.reached), "at", schedule=at)
    add_callback(sim, note("script"), "script")
    assert sim.run().status == "completed"
    assert list(sim.callbacks) == ["every", "third", "interval", "at", "script"]
    assert [s for n, s in seen if n == "every"] == list(range(1, 11))
    assert [s for n, s in seen if n == "third"] == [3, 6, 9]
    assert [s for n, s in seen if n == "interval"] == [4, 7]      # t = 0.4, 0.7 (0.35, 0.7)
    assert reached == [0.25, 0.5] and at.pending == [5.0]
    # after each step: the callbacks, in the order added (a script's one of them)
    assert [n for n, s in seen if s == 9] == ["every", "third", "script"]


def test_a_name_is_given_once() -> None:
    sim = loop()
    add_callback(sim, lambda s: None, "layer")
    with pytest.raises(ValueError, match="'layer' already"):
        add_callback(sim, lambda s: None, "layer")


class Part(Outputs):
    """A part that measures something: one column, one profile, cell data, a summary
    member and its share of the checkpoint, named after it."""

    def __init__(self, name: str) -> None:
        self.name, self.steps, self.rows = name, 0, 0
        self.columns = (f"{name}_steps",)

    def __call__(self, sim: Simulation) -> None:
        self.steps += 1

    def diagnostics(self, sim: Simulation, cell_speed: np.ndarray) -> dict[str, float]:
        return {f"{self.name}_steps": float(self.steps), "shared": float(len(cell_speed))}

    def record(self, row: dict[str, float]) -> None:
        self.rows += 1

    def profiles(self, t: float) -> dict[str, tuple[list[str], np.ndarray]]:
        return {f"{self.name}_line": (["x", "z"], np.full((2, 2), t))}

    def fields(self) -> dict[str, np.ndarray]:
        return {f"{self.name}_cells": np.arange(3.0)}

    def summary(self, result: Any) -> dict[str, Any]:
        return {f"{self.name}_steps": self.steps}

    def save_state(self) -> dict[str, Any]:
        return {f"{self.name}_saved": self.steps}

    def restore_state(self, state: dict[str, Any]) -> None:
        self.steps = int(state[f"{self.name}_saved"])


def test_the_walks_gather_what_each_part_declares_in_the_order_added() -> None:
    sim = loop(steps=4)
    layer, state = Part("layer"), Part("state")
    add_callback(sim, layer, "layer")
    add_callback(sim, lambda s: None, "plain")       # a plain callback declares nothing
    add_callback(sim, Callback(state, EveryNSteps(2)), "state")
    sim.run()
    walk = sim.callbacks
    assert walk.parts() == [layer, state]
    assert walk.columns() == ["layer_steps", "state_steps"]
    assert walk.diagnostics(sim, np.zeros(7)) == {"layer_steps": 4.0, "shared": 7.0,
                                                  "state_steps": 2.0}
    walk.record({})
    assert (layer.rows, state.rows) == (1, 1)
    assert list(walk.profiles(0.5)) == ["layer_line", "state_line"]
    assert list(walk.fields()) == ["layer_cells", "state_cells"]
    assert walk.summary(None) == {"layer_steps": 4, "state_steps": 2}
    assert walk.frame_source() is None
    saved = walk.save_state()
    layer.steps = state.steps = 0
    walk.restore_state(saved)
    assert (layer.steps, state.steps) == (4, 2)
