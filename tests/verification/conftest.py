"""Shared fixtures of the column verification tests: a short run of a built scenario, and
a run stopped, written to a checkpoint and restored beside its uninterrupted twin."""

from collections.abc import Callable
from pathlib import Path

import pytest

from granflow.config import load_config
from granflow.io.checkpoint import read_checkpoint, write_checkpoint
from granflow.io.run_dir import RunDir
from granflow.io.run_state import SimulationState
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


Twins = tuple[ColumnCollapse, ColumnCollapse, ColumnCollapse]
CheckpointTwins = Callable[[Callable[[str], ColumnCollapse], Path], Twins]


def _checkpoint_twins(column: Callable[[str], ColumnCollapse], root: Path) -> Twins:
    """(straight, first, twin): ``column`` run to 0.04 s; run to 0.02 s; a fresh build
    restored from ``first``'s checkpoint file (data only), not yet run on."""
    straight = column("time.t_end=0.04")
    straight.simulation.run()
    first = column("time.t_end=0.02")
    first.simulation.run()
    run_dir = RunDir.create(root / "run")
    write_checkpoint(run_dir, SimulationState(loop=first.simulation.save_state(),
                                              scenario=first.save_state(), outputs={}))
    saved = read_checkpoint(run_dir.root)
    twin = column("time.t_end=0.04")
    twin.restore_state(saved.scenario)
    twin.simulation.restore_state(saved.loop)
    return straight, first, twin


@pytest.fixture(scope="session")
def checkpoint_twins() -> CheckpointTwins:
    return _checkpoint_twins
