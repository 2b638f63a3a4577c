"""What a run will cost, from its configuration alone: settings that are valid one by one
but would compute for days are refused before anything starts, with the estimate and the
key to change; a run of more than an hour is announced (``cost_note``).

The estimate is a lower bound: the triangles the mesher will make (``estimated_triangles``)
times the fewest steps (time.t_end over time.dt or time.dt_max) times
``COST_PER_TRIANGLE_STEP``, the time one core takes per triangle and step at the default
tolerance, as ``benchmarks/scaling.py`` measured it from 300 to 80,000 triangles
(``tests/unit/test_cost.py`` holds it within that measurement). A column that stops at
rest (``time.stop_at_rest``) usually ends long before time.t_end, so its estimate is only
announced, never refused.

A tolerance below ``TOL_FLOOR`` is refused: the fixed-point iteration (3.2) does not reach
it in double precision. ``benchmarks/tolerance_floor.py`` runs a coarse column at
tolerances falling to round-off: down to the floor every step converges, below it the
attempts fail to converge and are retried smaller, at many times the cost
(``tests/unit/test_cost.py`` reads the floor from its results).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from granflow.config.kinds import rules_of

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config

COST_PER_TRIANGLE_STEP = 1e-4   # s of one core (module docstring)
MAX_HOURS = 24.0                # refused above (a lower bound of the run's time)
NOTE_HOURS = 1.0                # announced above
TOL_FLOOR = 1e-12               # smallest numerics.tol the iteration (3.2) reaches
MAX_OUTPUT_TIMES = 10_000       # each writes profiles and a VTU snapshot


def estimate(c: Config) -> tuple[float, float, float, str]:
    """(triangles, fewest steps, seconds of one core, the key that sets the step)."""
    t = c.time
    key, step = ("time.dt", t.dt) if t.dt is not None else ("time.dt_max", t.dt_max)
    triangles = sum(estimated_triangles(c))
    steps = t.t_end / step
    return triangles, steps, COST_PER_TRIANGLE_STEP * triangles * steps, key


def stops_at_rest(c: Config) -> bool:
    """Whether the run may end at rest long before time.t_end (its kind says)."""
    return rules_of(c).stops_at_rest(c)


def cost_problems(c: Config) -> Iterator[str]:
    """Settings that are valid one by one but absurd together (module docstring)."""
    t = c.time
    if c.numerics.tol < TOL_FLOOR:
        yield (f"numerics.tol = {c.numerics.tol!r} is below what the iteration (3.2) reaches "
               "in double precision: its steps would fail to converge and shrink without "
               f"end; use numerics.tol >= {TOL_FLOOR:g}")
    triangles, steps, seconds, key = estimate(c)
    if len(t.output_times) > min(MAX_OUTPUT_TIMES, steps):
        yield (f"time.output_times has {len(t.output_times)} times, more than "
               + (f"the {steps:.3g} steps of {key} = {t.dt or t.dt_max!r} to time.t_end"
                  if steps < MAX_OUTPUT_TIMES else f"{MAX_OUTPUT_TIMES} allowed")
               + "; each one writes profiles and a snapshot: give fewer")
    if seconds > 3600 * MAX_HOURS and not stops_at_rest(c):
        yield (f"this run needs at least {seconds / 3600:.3g} hours of computing ({steps:.2g} "
               f"steps of {key} = {t.dt or t.dt_max!r} to time.t_end = {t.t_end!r} on about "
               f"{triangles:.2g} triangles, at ~{COST_PER_TRIANGLE_STEP:g} s per triangle "
               f"and step; at most {MAX_HOURS:g} h allowed); use a larger {key}, a shorter "
               "time.t_end or a larger mesh.size")


def cost_note(c: Config) -> str | None:
    """One line announcing a run of more than ``NOTE_HOURS`` (None for a shorter one)."""
    triangles, steps, seconds, key = estimate(c)
    if seconds <= 3600 * NOTE_HOURS:
        return None
    rest = (" if it does not come to rest first" if stops_at_rest(c) else "")
    return (f"this run needs about {seconds / 3600:.2g} hours of computing or more{rest} "
            f"({steps:.2g} steps of {key} on about {triangles:.2g} triangles)")


def estimated_triangles(c: Config) -> tuple[float, float]:
    """Triangles the mesher will make (bulk, erodible layer): the kind's estimate."""
    return rules_of(c).triangles(c)
