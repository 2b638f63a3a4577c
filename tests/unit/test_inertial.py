"""The inertial numbers reached in a mu(I) run (diagnostics/inertial.py)."""

import math

import numpy as np
import pytest

from granflow.config import load_config
from granflow.diagnostics.inertial import InertialNumbers
from granflow.diagnostics.state import FLOWING_SPEED
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.sampling import cell_means
from granflow.runner import build_problem


def test_quantiles_of_the_histogram_match_the_weighted_sample_within_a_bin() -> None:
    rng = np.random.default_rng(3)
    values = 10.0 ** rng.uniform(-5.0, 0.0, 4000)
    weights = rng.uniform(0.5, 1.5, 4000)
    stats = InertialNumbers()
    stats.add(values[:1500], weights[:1500])
    stats.add(values[1500:], weights[1500:])
    order = np.argsort(values)
    cumulative = np.cumsum(weights[order]) / weights.sum()
    for q, key in ((0.05, "p05"), (0.5, "p50"), (0.95, "p95"), (0.99, "p99")):
        exact = values[order][np.searchsorted(cumulative, q)]
        assert exact <= stats.summary()[key] <= exact * 10 ** 0.05 * 1.0001   # one bin
    assert stats.summary()["max"] == values.max()


def test_no_flowing_cell_gives_no_summary() -> None:
    stats = InertialNumbers()
    stats.add(np.array([]), np.array([]))
    assert stats.summary() is None and stats.quantile(0.5) is None


def test_a_mu_i_collapse_records_the_inertial_numbers_of_its_flowing_cells() -> None:
    """Wiring: the run's largest recorded I is at least the largest I of the flowing cells
    of its last step, computed here from the final fields; Drucker-Prager records none."""
    config = load_config("rectangle-rigid", ["material.rheology=mu-i", "mesh.size=0.03",
                                             "time.t_end=0.03", "time.output_times=[]"])
    problem = build_problem(config)
    assert problem.simulation.run().status == "completed"
    assert problem.inertial is not None and problem.inertial.summary() is None  # no observer
    solver = problem.solver
    problem.measures.shape_measures(cell_means(problem.mesh, solver.velocity.Norm())[0])
    law = solver.rheology
    values, _ = cell_means(problem.mesh, law.inertial_number(
        math.sqrt(2.0) * solver.strain_rate_norm(), solver.pressure, NGSOLVE_OPS))
    speed, _ = cell_means(problem.mesh, solver.velocity.Norm())
    flowing = values[speed > FLOWING_SPEED]
    summary = problem.inertial.summary()
    assert len(flowing) > 0 and summary["max"] == pytest.approx(flowing.max(), rel=1e-12)
    assert summary["p05"] <= summary["p50"] <= summary["p95"] <= 1.13 * summary["max"]
    dp = build_problem(load_config("rectangle-rigid", ["mesh.size=0.03"]))
    assert dp.inertial is None
