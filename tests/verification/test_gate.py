"""A gate on the column's front face, withdrawn upwards (``geometry/gate.py``): it holds the
face above its lower end and lets the mass out below; its friction acts against its own
motion, the same in the fixed point (3.2) and in Newton's method."""

import numpy as np
import pytest

from granflow.ale.free_surface import BoundaryChain
from granflow.config import load_config
from granflow.fem.sampling import point_values
from granflow.geometry.labels import GATE
from granflow.scenarios.column import build_column

COARSE = ["mesh.size=0.02", "time.output_times=[]"]


def _run(overrides: list[str]):  # type: ignore[no-untyped-def]
    problem = build_column(load_config("rectangle-rigid", [*COARSE, *overrides]))
    area0 = problem.mover.area()
    return problem, problem.simulation.run(), area0


def test_the_gate_holds_the_face_above_its_lower_end() -> None:
    """A gate rising at 0.5 m/s for 0.1 s (a 5 cm opening): the face's nodes still on it
    lie on x = l0 and above the opening less half an edge; below it the mass has flowed out
    (its front beyond x = l0), though less far than released at once; the volume holds."""
    gated, result, area0 = _run(["time.t_end=0.1", "gate.enabled=true", "gate.speed=0.5"])
    assert result.status == "completed", result.message
    chain = BoundaryChain(gated.mesh)
    xy = gated.mesh.ngmesh.Coordinates()
    face = chain.vertices(GATE)
    assert len(face) and np.all(xy[face, 0] == 0.2)
    assert xy[face, 1].min() >= 0.05 - 0.5 * 0.02
    front = xy[:, 0].max()
    assert front > 0.2 + 0.005
    free, _, _ = _run(["time.t_end=0.1"])
    assert front < free.mesh.ngmesh.Coordinates()[:, 0].max() - 0.01
    assert gated.mover.area() == pytest.approx(area0, rel=1e-12)


@pytest.mark.slow   # about 90 s: the rough moving wall needs many iterations per step
def test_a_rising_gate_drags_the_grains_at_its_face_up() -> None:
    """With a rough gate (40 degrees) rising at 2 m/s, the material along the upper face
    moves up by more than 1 cm/s after 10 ms, while beside a gate that hardly moves (1 mm/s)
    it is held, moving no faster than the gate. The fixed point (3.2) gives Newton's velocity
    within 3 %: the moving wall's term is assembled at every iteration of both, and the
    fixed point, contracting slowly here, stops at a relative change of 1e-6 about 1 %
    from its limit (measured: 0.2 % and 1.4 % at the two points)."""
    common = ["time.t_end=0.01", "time.dt=1e-3", "gate.enabled=true", "gate.friction_deg=40",
              "numerics.tol=1e-6", "numerics.linearization=newton"]
    near = (0.195, np.array([0.10, 0.12]))          # 5 mm behind the face, high up

    def uz(problem) -> np.ndarray:  # type: ignore[no-untyped-def]
        _, u = point_values(problem.mesh, problem.solver.velocity, *near)
        return u[:, 1]

    fast, _, _ = _run([*common, "gate.speed=2.0"])
    slow, _, _ = _run([*common, "gate.speed=0.001"])
    assert np.all(uz(fast) > 0.01) and np.all(np.abs(uz(slow)) <= 0.001)
    picard, _, _ = _run([*common[:-1], "numerics.linearization=picard", "gate.speed=2.0"])
    assert uz(picard) == pytest.approx(uz(fast), rel=0.03)
