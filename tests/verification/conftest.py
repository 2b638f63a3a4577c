"""Shared fixture of the column verification tests: a short run of a built scenario."""

from collections.abc import Callable

import pytest

from granflow.config import load_config
from granflow.scenarios.column import ColumnCollapse, build_column
from granflow.simulation.simulation import RunResult

ShortRun = Callable[[str, list[str]], tuple[ColumnCollapse, RunResult, float]]


def _run_short_column(scenario: str, overrides: list[str]
                      ) -> tuple[ColumnCollapse, RunResult, float]:
    """Build ``scenario`` with ``overrides`` and run it: (problem, result, initial area)."""
    problem = build_column(load_config(scenario, overrides))
    area0 = problem.mover.area()
    return problem, problem.simulation.run(), area0


@pytest.fixture(scope="session")
def run_short_column() -> ShortRun:
    return _run_short_column
