"""The time loop is written against protocols: it imports and runs with NGSolve blocked."""

from __future__ import annotations

import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent("""
    import sys
    sys.modules["ngsolve"] = None        # any import of the engine now raises ImportError
    sys.modules["netgen"] = None
    from granflow.simulation.outcomes import IterationReport
    from granflow.simulation.rest import RestCriterion
    from granflow.simulation.simulation import Simulation
    from granflow.simulation.timestep import fixed_step

    class Decay:
        '''u' = -u by implicit Euler: the loop needs no more than the FlowStep protocol.'''
        def __init__(self):
            self.u = self.trial = 1.0
        def solve_step(self, dt, tol, max_iterations, velocity_floor=0.0):
            self.trial = self.u / (1.0 + dt)
            return IterationReport(converged=True, iterations=1, relative_change=0.0)
        def local_error(self, dt):
            return None
        def accept(self, dt=None):
            self.u = self.trial
        def reject(self):
            self.trial = self.u

    solver = Decay()
    sim = Simulation(solver=solver, steps_policy=fixed_step(1.0, 0.01, 1e-6), t_end=1.0,
                     max_iterations=5)
    result = sim.run()
    assert result.status == "completed" and result.steps == 100, result
    assert abs(solver.u - 1.01 ** -100) < 1e-12, solver.u
    assert not any(m.startswith(("ngsolve", "netgen")) and sys.modules[m] is not None
                   for m in sys.modules)
    print("ok")
""")


def test_the_loop_runs_without_the_finite_element_engine() -> None:
    done = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "ok"
