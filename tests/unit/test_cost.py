"""The cost rules stand on measurements: the cost per triangle and step is within what
benchmarks/scaling.py measured, the tolerance floor is where benchmarks/tolerance_floor.py
saw the iteration stop converging, and the estimate counts what it says."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from granflow.config import estimated_triangles, load_config
from granflow.config.cost import (
    COST_PER_TRIANGLE_STEP,
    MAX_HOURS,
    TOL_FLOOR,
    cost_note,
    cost_problems,
    estimate,
)

RESULTS = Path(__file__).parents[2] / "benchmarks" / "results"


def test_the_cost_per_triangle_step_is_the_measured_one() -> None:
    rows = json.loads((RESULTS / "scaling" / "scaling-pardiso.json").read_text())["rows"]
    measured = [row["step_s"] / row["n_triangles"] for row in rows]
    assert len(measured) >= 4
    assert min(measured) <= COST_PER_TRIANGLE_STEP <= max(measured)
    assert max(measured) < 2 * COST_PER_TRIANGLE_STEP      # a lower bound, within 2x


def test_the_tolerance_floor_is_where_the_iteration_stops_converging() -> None:
    rows = json.loads((RESULTS / "tolerance_floor" / "tolerance_floor.json").read_text())["rows"]
    at_or_above = [r for r in rows if r["tol"] >= TOL_FLOOR]
    below = [r for r in rows if r["tol"] < TOL_FLOOR]
    assert at_or_above and below
    assert all(r["rejected_steps"] == 0 and r["status"] == "completed" for r in at_or_above)
    floor = min(at_or_above, key=lambda r: r["tol"])
    assert all(r["rejected_steps"] > 10 * floor["steps"] for r in below)


def test_the_estimate_is_triangles_times_steps() -> None:
    config = load_config("rectangle-rigid", ["time.t_end=0.5", "time.dt_max=2e-3"])
    triangles, steps, seconds, key = estimate(config)
    assert triangles == pytest.approx(sum(estimated_triangles(config)))
    assert steps == pytest.approx(250) and key == "time.dt_max"
    assert seconds == pytest.approx(COST_PER_TRIANGLE_STEP * triangles * 250)
    assert cost_note(config) is None and list(cost_problems(config)) == []


def test_a_day_is_refused_unless_the_column_stops_at_rest() -> None:
    long = ["time.t_end=5000", "time.dt_max=1e-3"]
    stops = load_config("rectangle-rigid", long)
    assert estimate(stops)[2] > 3600 * MAX_HOURS
    assert list(cost_problems(stops)) == [] and "if it does not come to rest" in cost_note(stops)
    never = stops.model_copy(update={"time": stops.time.model_copy(
        update={"stop_at_rest": False})})
    (problem,) = cost_problems(never)
    assert "hours of computing" in problem and "time.dt_max" in problem
