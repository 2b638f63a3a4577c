"""Callbacks of the time loop and the schedules that trigger them, as Oceananigans'
``add_callback!(simulation, Callback(func, schedule); name)`` and
``simulation.callbacks[name]``: after each accepted step the loop runs every callback whose
schedule says so, in the order they were added. A callback's ``func`` that is an ``Outputs``
(``simulation/outputs.py``) also declares what the run's outputs read of it.

A schedule is ``schedule(sim) -> bool``: ``EveryStep``, ``EveryNSteps``, ``TimeInterval``,
``AtTimes``. Given an ``action``, the last three run it themselves (``AtTimes`` as
``action(sim, time)`` for each time reached), and can stand as a callback's func.
"""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

from tqdm import tqdm


class Simulation(Protocol):
    """What callbacks and schedules read of the running loop (``simulation.Simulation``):
    declared here, so that this module and ``outputs`` sit below the loop that walks them."""

    t: float
    dt: float
    step: int
    last_report: Any
    callbacks: Any


Action = Callable[[Simulation], Any]


class Schedule(Protocol):
    """Whether a callback is due after this accepted step (it may keep state: the next
    time, the times still pending)."""

    def __call__(self, sim: Simulation) -> bool: ...


@dataclass
class Callback:
    """``func(sim)`` after an accepted step when ``schedule(sim)`` says so."""

    func: Action
    schedule: Schedule = field(default_factory=lambda: EveryStep())

    def __call__(self, sim: Simulation) -> None:
        if self.schedule(sim):
            self.func(sim)


def add_callback(sim: Simulation, callback: Callback | Action, name: str,
                 schedule: Schedule | None = None, first: bool = False) -> Callback:
    """Add ``callback`` (or ``Callback(func, schedule)``) to ``sim.callbacks`` as ``name``,
    after those already there, or with ``first`` before them (a part whose declarations
    the others may refine: the run's own summary members); a name is given once."""
    if not isinstance(callback, Callback):
        callback = Callback(callback, schedule if schedule is not None else EveryStep())
    if name in sim.callbacks:
        raise ValueError(f"the simulation has a callback named {name!r} already")
    rest = dict(sim.callbacks) if first else {}
    for other in rest:
        del sim.callbacks[other]
    sim.callbacks[name] = callback
    sim.callbacks.update(rest)
    return callback


class EveryStep:
    """Every accepted step."""

    def __call__(self, sim: Simulation) -> bool:
        return True


class AtTimes:
    """Once when the loop reaches each of ``times`` (the steps hit them): runs
    ``action(sim, time)`` for each; ``flush`` runs the ones still pending from the final
    state. As a schedule (no action), due when one or more were reached (``reached``)."""

    def __init__(self, times: Sequence[float],
                 action: Callable[[Simulation, float], None] | None = None) -> None:
        self.pending = sorted(times)
        self.action = action
        self.reached: list[float] = []

    def __call__(self, sim: Simulation) -> bool:
        self.reached = []
        while self.pending and sim.t >= self.pending[0] - 1e-9 * max(1.0, self.pending[0]):
            t = self.pending.pop(0)
            self.reached.append(t)
            if self.action is not None:
                self.action(sim, t)
        return bool(self.reached)

    def flush(self, sim: Simulation) -> list[float]:
        """Write the pending times from the current state; return them."""
        done = list(self.pending)
        for t in done:
            if self.action is not None:
                self.action(sim, t)
        self.pending = []
        return done


class EveryNSteps:
    """Every ``n`` accepted steps (never when n == 0); runs ``action`` then, if given."""

    def __init__(self, n: int, action: Action | None = None) -> None:
        self.n, self.action = n, action

    def __call__(self, sim: Simulation) -> bool:
        due = self.n > 0 and sim.step % self.n == 0
        if due and self.action is not None:
            self.action(sim)
        return due


class TimeInterval:
    """Each time simulated time crosses a multiple of ``interval`` (``next``: the next
    one); runs ``action`` then, if given."""

    def __init__(self, interval: float, action: Action | None = None) -> None:
        self.interval, self.action, self.next = interval, action, interval

    def __call__(self, sim: Simulation) -> bool:
        if not (self.interval > 0 and sim.t >= self.next - 1e-12):
            return False
        if self.action is not None:
            self.action(sim)
        while self.next <= sim.t + 1e-12:
            self.next += self.interval
        return True


class ProgressBar:
    """A tqdm bar over simulated time showing dt, iterations and an ETA."""

    def __init__(self, t_end: float, enabled: bool = True, initial: float = 0.0) -> None:
        self.enabled = enabled
        self.bar = _bar_class()(
            total=t_end, initial=initial, unit="s", disable=not enabled, dynamic_ncols=True,
            bar_format="{l_bar}{bar}| t={n:.4f}/{total:.3g} s [{elapsed}]{postfix}")

    def __call__(self, sim: Simulation) -> None:
        self.bar.update(sim.dt)
        report = sim.last_report
        self.bar.set_postfix_str(
            f"dt={sim.dt:.2e} it={report.iterations if report else 0}{self._eta(sim.t)}",
            refresh=False)

    def _eta(self, t: float) -> str:
        """Remaining wall time at the average pace so far (from the bar's own clock and
        start); none in the first tenth of the run, whose tiny first steps predict hours."""
        if not self.enabled:          # a disabled tqdm keeps no count or clock
            return ""
        bar = self.bar
        done, total = t - bar.initial, bar.total - bar.initial
        if done <= 0 or done < 0.1 * total:
            return ""
        remaining = bar.format_dict["elapsed"] * (bar.total - t) / done
        return f" eta<{remaining:.0f}s"

    def close(self, note: str = "", complete: bool = False) -> None:
        """Close the bar with ``note`` after it (why it stopped short of t_end, say);
        ``complete``: the run ended early as it should (at rest), so the bar ends at 100 %
        of the time it ran."""
        if complete and self.enabled and self.bar.n > 0:
            self.bar.total = self.bar.n
        if note:
            self.bar.set_postfix_str(note, refresh=False)
        self.bar.refresh()
        self.bar.close()

    def say(self, text: str) -> None:
        """A line under the closed bar: what the run does next, so the screen is not silent."""
        if self.enabled:
            tqdm.write(text)


def _bar_class() -> Any:
    """tqdm's notebook widget in a Jupyter kernel that has ipywidgets, else the text bar
    (which a notebook without ipywidgets shows as updating text)."""
    if "ipykernel" in sys.modules:
        try:
            import ipywidgets  # noqa: F401
            from tqdm.notebook import tqdm as notebook_bar
        except ImportError:
            return tqdm
        return notebook_bar
    return tqdm
