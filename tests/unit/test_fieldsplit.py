"""``numerics.linear_solver = 'fieldsplit'`` (``fem/fieldsplit.py``): refused in one line in
2D and where petsc4py or ngspetsc is not installed (CI: neither is); where they are,
one 3D Picard and one Newton system solved by it against the direct solve, and a solve
stopped short of its tolerance raising ``LinearSolveFailed``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import ngsolve as ngs
import numpy as np
import pytest

from granflow.app.cli import main
from granflow.config import ConfigError, load_config

SETS_3D = ["geometry.dimension=3", "mesh.size=0.07", "boundary.channel_width=0.1",
           "boundary.non_penetration=strong", "numerics.linear_solver=fieldsplit"]
# The fieldsplit solution's distance to the direct one, relative, in the velocity's and
# the pressure's Euclidean norms: FGMRes stops at a true relative residual of 1e-10 of the
# scaled system (the velocity's inner solve at 1e-4); on the column's systems at 973 to
# 18,192 unknowns that leaves both fields within 1e-7 of the direct solve (docs/three_d.md),
# so 1e-4 leaves room and still catches a wrong solve.
AGREEMENT = 1e-4


def test_refused_in_two_dimensions() -> None:
    with pytest.raises(ConfigError, match=r"numerics.linear_solver = 'fieldsplit'.*3D"):
        load_config("rectangle-rigid", ["numerics.linear_solver=fieldsplit"])


def test_refused_in_one_line_without_petsc(monkeypatch: pytest.MonkeyPatch, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    from granflow.fem import fieldsplit

    monkeypatch.setattr(fieldsplit, "petsc_missing", lambda: "petsc4py")
    code = main(["run", "rectangle-rigid", *(a for s in SETS_3D for a in ("--set", s)),
                 "--out", str(tmp_path / "run"), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1
    assert "numerics.linear_solver = 'fieldsplit' needs petsc4py and ngspetsc" in err
    assert "'auto'" in err
    assert not (tmp_path / "run" / "summary.json").exists()      # nothing computed


def test_petsc_missing_names_what_is_not_installed() -> None:
    from importlib.util import find_spec

    from granflow.fem.fieldsplit import petsc_missing

    installed = find_spec("petsc4py") is not None and find_spec("ngsPETSc") is not None
    assert (petsc_missing() is None) == installed
    if not installed:
        assert petsc_missing() in ("petsc4py", "ngspetsc")


def _flow(linearization: str):
    """A 3D column's flow solver (fieldsplit) at a slumping state, ready to assemble."""
    from granflow.fem.flow_factory import build_flow
    from granflow.geometry.mesh3d import extruded_mesh
    from granflow.scenarios.channel_setup import ChannelSetup

    config = load_config("rectangle-rigid", [*SETS_3D,
                                             f"numerics.linearization={linearization}"])
    setup = ChannelSetup.of(config)
    solver = build_flow(extruded_mesh(setup.section, setup.span, setup.size), setup.flow)
    velocity, pressure = solver.solution.components
    pressure.Set(1550 * 9.81 * (0.14 - ngs.z))
    velocity.Set(ngs.CF((ngs.x * ngs.z, 0.0, -0.5 * ngs.z * ngs.z)) / (0.2 * 0.14)
                 * ngs.IfPos(ngs.x - 0.1, 1.0, 0.1))
    solver.previous.vec.data = solver.solution.vec
    solver.scheme.begin_step(1e-3)
    return solver


def _apart(solver, a: ngs.BaseVector, b: ngs.BaseVector) -> list[float]:
    split = solver.space.Range(0).stop
    x, y = a.FV().NumPy(), b.FV().NumPy()
    return [float(np.linalg.norm(x[s] - y[s]) / np.linalg.norm(y[s]))
            for s in (slice(0, split), slice(split, None))]


def _assembled_picard(solver: Any) -> Any:
    """The flow solver's Picard system, its matrix and right-hand side assembled."""
    picard = solver.nonlinear.picard_system
    picard.prepare()
    picard.assemble()
    return picard


@pytest.mark.parametrize("system", ["picard", "newton"])
def test_fieldsplit_solves_as_the_direct_solve(system: str) -> None:
    pytest.importorskip("petsc4py")
    pytest.importorskip("ngsPETSc")
    from granflow.fem.fieldsplit import FieldsplitSolve
    from granflow.fem.linalg import ReusableLU

    solver = _flow(system)
    nonlinear = solver.nonlinear
    if system == "picard":
        picard = _assembled_picard(solver)
        form, rhs = picard.a, picard.f.vec
    else:
        newton = nonlinear.newton_system
        newton.form.AssembleLinearization(solver.solution.vec)
        rhs = solver.solution.vec.CreateVector()
        newton.residual(solver.solution.vec, rhs)
        form = newton.form
    lu = (picard if system == "picard" else newton).lu
    assert isinstance(lu, FieldsplitSolve)
    fieldsplit, direct = rhs.CreateVector(), rhs.CreateVector()
    lu.update()
    lu.solve(rhs, fieldsplit)
    exact = ReusableLU(form, solver.space.FreeDofs(), "umfpack")
    exact.update()
    exact.solve(rhs, direct)
    assert lu.steps > 0
    assert max(_apart(solver, fieldsplit, direct)) < AGREEMENT


def test_a_solve_short_of_its_tolerance_fails() -> None:
    pytest.importorskip("petsc4py")
    pytest.importorskip("ngsPETSc")
    from granflow.fem.fieldsplit import FieldsplitSolve, LinearSolveFailed

    solver = _flow("picard")
    picard = _assembled_picard(solver)
    short = FieldsplitSolve(picard.a, solver.space.FreeDofs(), max_steps=2)
    short.update()
    with pytest.raises(LinearSolveFailed, match="stopped after 2 steps"):
        short.solve(picard.f.vec, picard.f.vec.CreateVector())


def test_the_krylov_work_combines_over_solves_and_a_direct_solve_has_none() -> None:
    from granflow.fem.fieldsplit import KRYLOV_KEYS, combined_work

    first = dict(zip(KRYLOV_KEYS, (30, 3, 12), strict=True))
    second = dict(zip(KRYLOV_KEYS, (50, 2, 40), strict=True))
    assert combined_work({}, first, {}, second) == dict(
        zip(KRYLOV_KEYS, (80, 5, 40), strict=True))
    assert combined_work({}, {}) == {}


def test_a_fieldsplit_run_writes_its_krylov_work(tmp_path: Path) -> None:
    """summary.json of a fieldsplit run holds its GMRes steps, its solves and the most
    steps of one solve; every solve took at least one step and at most the limit."""
    pytest.importorskip("petsc4py")
    pytest.importorskip("ngsPETSc")
    import json

    from granflow.fem.fieldsplit import MAX_STEPS

    code = main(["run", "rectangle-rigid", *(a for s in SETS_3D for a in ("--set", s)),
                 "--set", "time.t_end=0.002", "--out", str(tmp_path / "run"), "--quiet"])
    assert code == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    steps, solves, largest = (summary[k] for k in (
        "krylov_iterations", "krylov_solves", "krylov_largest"))
    assert solves >= summary["nonlinear_iterations"] > 0
    assert solves <= steps <= solves * largest
    assert 0 < largest <= MAX_STEPS


def test_the_solver_of_a_new_mesh_carries_the_krylov_work_on() -> None:
    """After a remesh the new flow solver's counts start from the old one's (``inherit``;
    here the "new mesh" is the same one, the fields copied)."""
    pytest.importorskip("petsc4py")
    pytest.importorskip("ngsPETSc")
    from granflow.fem.coupling import Carriers

    old = _flow("picard")
    picard = _assembled_picard(old)
    picard.lu.update()
    picard.lu.solve(picard.f.vec, picard.f.vec.CreateVector())
    work = old.linear_work()
    assert work["krylov_solves"] == 1 and work["krylov_iterations"] > 0

    def copy(a: ngs.GridFunction, b: ngs.GridFunction) -> None:
        b.vec.data = a.vec

    new = _flow("picard")
    assert new.linear_work()["krylov_solves"] == 0
    new.inherit(old, Carriers(copy, copy, copy, copy))
    assert new.linear_work() == work


def test_the_time_loop_retries_a_failed_solve_smaller() -> None:
    """A fieldsplit solve stopped short fails the step: rejected, then retried at half
    the step (the loop's path for a solver error), not accepted."""
    from granflow.fem.fieldsplit import LinearSolveFailed
    from granflow.simulation.outcomes import IterationReport
    from granflow.simulation.simulation import Simulation
    from granflow.simulation.timestep import fixed_step

    class FailingOnce:
        def __init__(self) -> None:
            self.attempts: list[float] = []

        def solve_step(self, dt: float, tol: float, max_iterations: int,
                       velocity_floor: float = 0.0) -> IterationReport:
            self.attempts.append(dt)
            if len(self.attempts) == 1:
                raise LinearSolveFailed("the fieldsplit FGMRes stopped after 400 steps")
            return IterationReport(converged=True, iterations=1, relative_change=0.0)

        def local_error(self, dt: float) -> tuple[float, float] | None:
            return None

        def accept(self, dt: float | None = None) -> None: ...
        def reject(self) -> None: ...
        def restart_history(self) -> None: ...

    solver = FailingOnce()
    simulation = Simulation(solver=solver, steps_policy=fixed_step(0.01, 1e-3, 1e-3),  # type: ignore[arg-type]
                            t_end=2e-3, max_iterations=10)
    result = simulation.run()
    assert result.status == "completed"
    assert result.rejections == {"exception": 1}
    assert solver.attempts[:2] == [1e-3, 5e-4]


def test_the_cost_crossover_solves_the_fitted_lines() -> None:
    """benchmarks/common/fieldsplit_cost.py: where k_i N^a_i / (P e) meets k_d N^a_d, the
    per-rank floor on P ranks, and no crossing where the direct solve grows no faster."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
    from common.fieldsplit_cost import EFFICIENCY, PER_RANK, crossover

    direct, iterative = (1e-8, 2.0), (1e-5, 1.0)
    assert crossover(direct, iterative) == pytest.approx(1e3)
    assert crossover(direct, (1.0, 1.0), ranks=64) == pytest.approx(1e8 / (64 * EFFICIENCY))
    assert crossover(direct, iterative, ranks=16) == 16 * PER_RANK
    assert crossover((1e-8, 1.0), iterative) is None
