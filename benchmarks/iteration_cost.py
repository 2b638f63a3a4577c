"""Benchmark: what one fixed-point iteration (3.2) costs, and two ways that
were tried to make it cheaper.

Run: python benchmarks/iteration_cost.py [--scenario trapezoid-rigid] [--at 0.3]
         [--window 0.05] [--repeat 40] [--out benchmarks/results/iteration_cost]

The scenario is run (its defaults) to t = AT; on that state, medians over REPEAT calls of:
the assembly of the iterate-dependent matrix (as granflow builds it, and with its
integrands compiled by NGSolve's ``Compile()``, also ``realcompile=True``: the matrices
are compared entry by entry), the numeric refactorisation, the back-substitution. Then the
run goes on for WINDOW seconds with every iteration after a step's first also solved by
GMRES (tol 1e-10) preconditioned with that step's first factorisation, the candidate
"reuse the LU across iterations": the GMRES iteration counts are recorded (the run itself
still uses its own solves). Writes OUT/ITERATION_COST.json and prints the figures.
"""

from __future__ import annotations

import argparse
import collections
import json
import statistics
import time
from collections.abc import Callable
from pathlib import Path

import ngsolve as ngs
import numpy as np
from common.results import write_json
from ngsolve.krylovspace import GMResSolver

import granflow.fem.nonlinear as nonlinear
from granflow.config import load_config
from granflow.fem.forms import _symbols
from granflow.runner import build_problem


def median_ms(call: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def assembly_variants(solver, repeat: int) -> dict:
    """Median assembly time of the iterate-dependent matrix, plain and compiled, and the
    largest difference of the compiled matrices from the plain one."""
    symbols = _symbols(solver.space, solver.solution, solver.coordinates)
    out, reference = {}, None
    for label, compiled in (("plain", None), ("compiled", False), ("realcompiled", True)):
        form = ngs.BilinearForm(solver.space)
        for term in solver.terms:
            lhs = term.lhs(symbols, solver.mesh)
            if lhs is None or getattr(term, "step_constant", False):
                continue
            form += lhs if compiled is None else lhs.Compile(realcompile=compiled, wait=True)
        try:
            form.Assemble()
        except Exception as exc:  # realcompile needs a C++ compiler at run time
            out[label] = {"error": f"{type(exc).__name__}: {exc}"}
            continue
        values = form.mat.AsVector().FV().NumPy().copy()
        reference = values if reference is None else reference
        out[label] = {"assemble_ms": median_ms(form.Assemble, repeat),
                      "max_difference": float(np.abs(values - reference).max())}
    return out


def term_costs(solver, repeat: int) -> dict:
    """Median assembly time (ms) of each term of (3.2) on its own: the ones read at the
    iterate (reassembled every iteration) and the step-constant ones (once a step)."""
    symbols = _symbols(solver.space, solver.solution, solver.coordinates)
    out = {}
    for term in solver.terms:
        lhs = term.lhs(symbols, solver.mesh)
        if lhs is None:
            continue
        form = ngs.BilinearForm(solver.space)
        form += lhs
        form.Assemble()
        key = type(term).__name__ + (" (once a step)" if getattr(term, "step_constant", False)
                                     else "")
        out[key] = out.get(key, 0.0) + median_ms(form.Assemble, repeat)
    return out


def mesh_velocity_cost(problem, repeat: int) -> dict:
    """The mesh velocity (3.6) of one step: its solve as the mover does it (assembly and
    factorisation of the moved mesh's elasticity matrix, then the solve)."""
    mover = problem.simulation.mesh_motion
    dt = problem.simulation.dt or 1e-3
    return {"prepare_ms": median_ms(lambda: mover.prepare(dt), repeat)}


def gmres_with_first_lu(problem, window: float) -> dict:
    """GMRES iterations needed by each later iteration of a step when preconditioned with
    the step's first factorisation (the run goes on with its own direct solves)."""
    counts: collections.Counter = collections.Counter()
    state: dict = {"inverse": None}
    iterate, prepare = nonlinear.FixedPointSystem.iterate, nonlinear.FixedPointSystem.prepare

    def prepare_and_forget(self) -> None:
        state["inverse"] = None
        prepare(self)

    def iterate_and_count(self, out, corrected: bool = False) -> None:
        self.assemble(corrected)
        rhs = self.f.vec.CreateVector()
        rhs.data = self.f.vec
        if corrected and self.correction is not None:
            self.correction[1].Assemble()
            rhs.data += self.correction[1].vec
        if state["inverse"] is None:
            copy = self.a.mat.CreateMatrix()
            copy.AsVector().data = self.a.mat.AsVector()
            state["matrix"] = copy
            state["inverse"] = copy.Inverse(self.lu._freedofs, inverse="pardiso")
        else:
            solution = rhs.CreateVector()
            solution[:] = 0.0
            gmres = GMResSolver(self.a.mat, state["inverse"], tol=1e-10, maxiter=100)
            gmres.Solve(rhs, solution)
            counts[gmres.iterations] += 1
        self.lu.update()
        self.lu.solve(rhs, out)

    nonlinear.FixedPointSystem.iterate = iterate_and_count
    nonlinear.FixedPointSystem.prepare = prepare_and_forget
    try:
        sim = problem.simulation
        sim.t_end = sim.t + window
        sim.run()
    finally:
        nonlinear.FixedPointSystem.iterate, nonlinear.FixedPointSystem.prepare = iterate, prepare
    its = sorted(counts.elements())
    return {"solves": len(its), "median": statistics.median(its) if its else None,
            "max": max(its, default=None), "histogram": dict(sorted(counts.items()))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="trapezoid-rigid")
    parser.add_argument("--at", type=float, default=0.3)
    parser.add_argument("--window", type=float, default=0.05)
    parser.add_argument("--repeat", type=int, default=40)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/iteration_cost"))
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    args = parser.parse_args()
    config = load_config(args.scenario, [*args.overrides, f"time.t_end={args.at}",
                                         "output.progress=false", "time.output_times=[]"])
    problem = build_problem(config)
    problem.simulation.run()
    solver = problem.solver
    system = solver.nonlinear.picard_system
    system.prepare()
    system.assemble()
    system.lu.update()
    solution = system.f.vec.CreateVector()
    result = {
        "scenario": args.scenario, "t": problem.simulation.t, "triangles": solver.mesh.ne,
        "dofs": solver.space.ndof,
        "assembly": assembly_variants(solver, args.repeat),
        "assembly_by_term_ms": term_costs(solver, args.repeat),
        "mesh_velocity": mesh_velocity_cost(problem, args.repeat),
        "factorise_ms": median_ms(system.lu.update, args.repeat),
        "back_substitute_ms": median_ms(lambda: system.lu.solve(system.f.vec, solution),
                                        args.repeat),
        "gmres_first_lu": gmres_with_first_lu(problem, args.window),
        "window_s": args.window,
    }
    print(json.dumps(result, indent=1))
    write_json(args.out / f"{args.scenario}_t{args.at:g}.json", result)


if __name__ == "__main__":
    main()
