"""Newton's consistent tangent (fem/forms.py) against finite differences, and the one
statement of each term shared by Picard and Newton."""

import ngsolve as ngs
import numpy as np
import pytest

from granflow.fem.flow import FlowSolver
from granflow.fem.flow_factory import FlowSpec, GivenLaw, SolverChoice, Terms, build_flow
from granflow.fem.forms import FrictionWall
from granflow.geometry.mesh import BED, SURFACE, WALL, polygon_mesh
from granflow.physics import CoulombFriction, DruckerPrager


@pytest.fixture(scope="module")
def solver() -> FlowSolver:
    """A small column with walls, moving mesh velocity and a flowing, compressed state.

    eps = 1e-2 and eps_f = 1e-3 keep the regularised laws smooth on the scale of the
    finite-difference step; the state keeps p and the friction load positive, away from
    the kinks of [.]_+.
    """
    mesh = polygon_mesh([(0, 0), (0.3, 0), (0.2, 0.2), (0, 0.2)],
                        [BED, SURFACE, SURFACE, WALL], 0.06)
    s = build_flow(mesh, FlowSpec(
        GivenLaw(DruckerPrager(1.0, 25.5, 1e-2), 1550.0),
        Terms((0.0, -9.81), walls=(FrictionWall(BED, CoulombFriction(25.5, 1e-3)),
                                   FrictionWall(WALL, CoulombFriction(10.2, 1e-3))),
              penalty=1e6),
        solver=SolverChoice("newton")))
    x, z = ngs.x, ngs.y
    s.set_state(ngs.CF((0.3 * x * (1 + z) + 0.05, -0.2 * z * z + 0.1 * x)),
                1550 * 9.81 * (0.25 - z) + 200 * x)
    s.mesh_velocity.Set(ngs.CF((0.1 * z, 0.05 * x)))
    s.dt.Set(1e-3)
    s.solution.vec.data = s.previous.vec
    s.solution.components[0].Set(ngs.CF((0.4 * x * (1 + z) + 0.04, -0.3 * z * z + 0.2 * x)))
    return s


def residual(s: FlowSolver, vec: ngs.BaseVector) -> np.ndarray:
    out = vec.CreateVector()
    s.nonlinear.newton_system.residual(vec, out)
    return out.FV().NumPy().copy()


def test_newton_tangent_matches_central_finite_differences(solver: FlowSolver) -> None:
    s = solver
    x = s.solution.vec
    form = s.nonlinear.newton_system.form
    form.AssembleLinearization(x)
    rng = np.random.default_rng(1)
    direction = x.CreateVector()
    direction.FV().NumPy()[:] = rng.standard_normal(len(direction)) * 1e-2
    tangent = direction.CreateVector()
    tangent.data = form.mat * direction
    h = 1e-5
    plus, minus = x.CreateVector(), x.CreateVector()
    plus.data = x + h * direction
    minus.data = x - h * direction
    fd = (residual(s, plus) - residual(s, minus)) / (2 * h)
    exact = tangent.FV().NumPy()
    assert np.linalg.norm(fd - exact) < 1e-6 * np.linalg.norm(exact)
    # and a tangent that ignores the pressure dependence of kappa would fail this test:
    assert np.linalg.norm(exact) > 0


def test_picard_and_newton_share_the_residual(solver: FlowSolver) -> None:
    """At any state, A(x) x - f of the fixed-point forms equals the Newton residual R(x)."""
    s = solver
    picard = s.nonlinear.picard_system
    picard.prepare()
    picard.assemble()
    ax = s.solution.vec.CreateVector()
    ax.data = picard.a.mat * s.solution.vec
    ax.data -= picard.f.vec
    newton = residual(s, s.solution.vec)
    assert np.linalg.norm(ax.FV().NumPy() - newton) < 1e-10 * np.linalg.norm(newton)


def test_newton_converges_quadratically_where_picard_crawls() -> None:
    """A plug-flow layer at eps = 1e-6: Newton needs a few iterations per step, the
    fixed-point iteration (3.2) dozens (the paper: 5,086 for 64 steps)."""
    from granflow.config import load_config
    from granflow.scenarios.plug_flow import build_plug_flow

    counts = {}
    for method in ("picard", "newton"):
        problem = build_plug_flow(load_config("plug-flow", [
            "mesh.size=0.5", "time.t_end=0.0312", f"numerics.linearization={method}",
            "time.output_times=[]"]))
        result = problem.simulation.run()
        assert result.status == "completed"
        counts[method] = result.nonlinear_iterations
    assert counts["newton"] * 3 < counts["picard"]
