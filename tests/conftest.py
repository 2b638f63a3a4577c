"""Shared fixtures: run the ``granflow`` command in a fresh folder. Every test under
verification/ compares a solver's results with a reference or a tolerance: it is marked
``numerics`` (round-off may move its results within their tolerances), and CI runs those
again with MKL's kernels of the other mode (.ci/run)."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest


@pytest.fixture
def granflow_cli(tmp_path: Path) -> Callable[..., subprocess.CompletedProcess[str]]:
    """Run ``python -m granflow ARGS`` with cwd = tmp_path; returns the completed process."""

    def run(*args: str, timeout: float = 120) -> subprocess.CompletedProcess[str]:
        env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}
        return subprocess.run([sys.executable, "-m", "granflow", *args], cwd=tmp_path,
                              capture_output=True, text=True, timeout=timeout, env=env)

    return run


VERIFICATION = Path(__file__).resolve().parent / "verification"


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        if VERIFICATION in Path(item.path).parents:
            item.add_marker(pytest.mark.numerics)
