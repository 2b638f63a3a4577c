"""Rung 2: the 2D plug flow against the independent 1D solver of (4.1), paper Tables 1-2.

Coarse cells only (dZ = 0.25 m); the full tables are benchmarks/plug_flow_tables.py.
"""

import math

import numpy as np
import pytest

from granflow.verify import paper_table, run_cell


def paper(table: int, eps: float, dt: float, dz: float) -> dict[str, float]:
    return next(r for r in paper_table(table)
                if r.get("eps", 1e-6) == eps and r["dt"] == dt and r["dZ"] == dz)


@pytest.fixture(scope="module")
def eps6_cells() -> dict[float, float]:
    return {dt: run_cell(1e-6, dt, 0.25)[0] for dt in (2.5e-2, 1.25e-2, 6.25e-3)}


def test_table1_small_eps_within_twice_the_paper(eps6_cells: dict[float, float]) -> None:
    """Acceptance: error <= 2 x paper for eps = 1e-6 (and 1e-4 below)."""
    for dt, error in eps6_cells.items():
        assert error <= 2 * paper(1, 1e-6, dt, 0.25)["error"], dt
    error_4 = run_cell(1e-4, 1.25e-2, 0.25)[0]
    assert error_4 <= 2 * paper(1, 1e-4, 1.25e-2, 0.25)["error"]


def test_table1_first_order_in_time(eps6_cells: dict[float, float]) -> None:
    """eps = 1e-6: implicit Euler converges at order 1 at the coarse steps (fit of log-log)."""
    dts = np.array(sorted(eps6_cells))
    errors = np.array([eps6_cells[dt] for dt in dts])
    slope = np.polyfit(np.log(dts), np.log(errors), 1)[0]
    assert 0.9 < slope < 1.1


@pytest.mark.parametrize("dt", [1.25e-2, 6.25e-3])
def test_table1_regularisation_error_matches_paper(dt: float) -> None:
    """eps = 1e-2: the regularisation error dominates and is within +-20 % of the paper."""
    error = run_cell(1e-2, dt, 0.25)[0]
    assert error == pytest.approx(paper(1, 1e-2, dt, 0.25)["error"], rel=0.20)


def test_strip_gives_the_paper_domain_solution() -> None:
    """The 2-cell strip used by `verify` reproduces the 1.5 m domain (shift invariance)."""
    wide = run_cell(1e-2, 2.5e-2, 0.25, extra=("geometry.length=1.5", "mesh.cells_x=6"))
    narrow = run_cell(1e-2, 2.5e-2, 0.25)
    assert wide[0] == pytest.approx(narrow[0], rel=1e-6)
    assert wide[1] == narrow[1]


def test_table2_moving_mesh_error_and_volume() -> None:
    """Vertical mesh velocity: error <= 2 x paper, relative volume error <= 1e-4."""
    row = paper(2, 1e-6, 1.56e-3, 0.25)
    error, _, volume_error, _ = run_cell(1e-6, 1.56e-3, 0.25, moving=True)
    assert error <= 2 * row["error_u"]
    assert volume_error <= 1e-4
    assert math.isfinite(volume_error)
