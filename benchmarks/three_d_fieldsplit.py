"""Benchmark: PETSc's own block preconditioners (PCFIELDSPLIT, no external package) on the
3D systems of (3.2) that ``three_d_krylov.py`` builds, against the direct solve (UMFPACK).

Run: python benchmarks/three_d_fieldsplit.py [--state rest flowing front] [--size 0.04 0.02]
         [--eps 1e-6] [--variants lsc-lu lsc-gamg selfp-lu selfp-gamg mass-lu]
         [--out benchmarks/results/three_d_krylov]
     [mpiexec -n 2] python benchmarks/three_d_fieldsplit.py --ranks [--state ...] [--size ...]
         [--variant cahouet-chabard] [--rigid-modes] [--scaled] [--history]
         [--out benchmarks/results/three_d_fieldsplit]
     python benchmarks/three_d_fieldsplit.py --table --out benchmarks/results/three_d_fieldsplit

Needs petsc4py (PETSc built without external packages is enough); without it the script
says so in one line and exits. One process. The system is ``three_d_krylov.py``'s: the
column (rectangle-rigid in half a 10 cm channel, walls' u.N = 0 held strongly) at
mesh.size, one Picard iteration's matrix at the iterate ``rest``, ``flowing`` or ``front``.
Its free dofs go to PETSc as one AIJ matrix with two index sets (velocity, pressure); GMRes
(unrestarted, at most --max-steps, relative preconditioned residual 1e-8, as
``three_d_krylov.py``; the unpreconditioned one is recorded too) is
preconditioned by the Schur complement factorisation ``full`` with, by variant:

- ``lsc-lu`` / ``lsc-gamg``: the Schur complement approximated by PETSc's least-squares
  commutator scaled by the velocity block's diagonal (``-pc_lsc_scale_diag``: the scaled
  BFBt of May and Moresi 2008 for variable-viscosity Stokes), its pressure Poisson solve by
  LU; the velocity block by LU or by GAMG (one V-cycle);
- ``selfp-lu`` / ``selfp-gamg``: the Schur complement approximated by
  A11 - A10 diag(A00)^-1 A01, inverted by LU / by GAMG, the velocity block by LU / GAMG;
- ``mass-lu``: the pressure mass weighted by 2 / m (the inverse effective viscosity, as in
  ``common/block_preconditioner.py``) by its diagonal, the velocity block by LU.

Per case: converged or not, FGMRes steps, processor seconds of the set-up and the solve,
the relative distance to the direct solution. Writes fieldsplit_<state>_h<size>.json under
--out; the prediction is benchmarks/results/three_d_krylov/PREDICTION_fieldsplit.md.

``--ranks``: ``selfp-gamg`` (or ``--variant selfp-gamg-flexible``, granflow's first solve)
alone on the mesh distributed by NGSolve over the ranks of
``mpiexec`` (rank 0 keeps no element, as in ``three_d_krylov.py``), the matrix and the
vectors handed to PETSc by ngspetsc (``Matrix``, ``VectorMapping``: PETSc spreads the rows
evenly over the ranks), against NGSolve's direct solve (``masterinverse`` on more than one
rank, UMFPACK on one); the processor seconds of each rank and the floating-point
operations PETSc counts on it in the set-up and the solve, the velocity's and the
pressure's L2 norms (to compare one rank with two). Writes
fieldsplit_ranks_<state>_h<size>_n<ranks>.json; with ``--rigid-modes`` GAMG is told the
velocity's rigid-body modes (its near-null space, as granflow's
``numerics.linear_solver = 'fieldsplit'`` does): fieldsplit_ranks_rigid_*.json, with
``--variant selfp-gamg-flexible`` fieldsplit_ranks_flexible[_rigid]_*.json, with the
other flexible variants (``cahouet-chabard``: the Cahouet-Chabard Schur preconditioner
assembled by NGSolve, applied by a PETSc shell; ``lsc-gamg-flexible``)
fieldsplit_ranks_<variant>[_rigid]_*.json; ``--scaled`` scales the system by its diagonal
as granflow's solve does (``_scaled`` in the name), ``--tolerance`` sets FGMRes' relative
residual; ``--history`` records the residuals and the distances to the direct solve after
every step (one process). ``--table`` prints the table of the FGMRes variants' records in
--out and writes table.json there (with the stopping test's ranges); docs/three_d.md
quotes it. The solver and the conversion are granflow's (``granflow.fem.fieldsplit``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from common.fieldsplit_table import TABLE_KINDS, stopping, table

from granflow.fem.fieldsplit import TOLERANCE, VARIANTS, configure


def petsc():
    """petsc4py's PETSc, or None where it is not installed."""
    try:
        from petsc4py import PETSc
    except ImportError:
        return None
    return PETSc


def to_petsc(PETSc, matrix, free):
    """The free rows and columns of an NGSolve sparse matrix as a PETSc AIJ matrix."""
    import numpy as np
    import scipy.sparse as sp

    rows, cols, vals = matrix.COO()
    csr = sp.csr_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))),
                        shape=matrix.shape)[free][:, free].tocsr()
    mat = PETSc.Mat().createAIJ(size=csr.shape, csr=(
        csr.indptr.astype(PETSc.IntType), csr.indices.astype(PETSc.IntType), csr.data))
    mat.assemble()
    return mat


def picard_system(state: str, size: float, eps: float, dt: float, comm):
    """The column's first Picard system (3.2) at ``state`` (rest, flowing or front: the
    velocity three_d_krylov.py sets), assembled on ``comm``'s ranks (None: one process):
    the solver, its matrix and its right-hand side."""
    import ngsolve as ngs
    from three_d_krylov import FRONT, system

    solver, slump, hydrostatic = system("column", eps, size, comm)
    velocity, pressure = solver.solution.components
    pressure.Set(hydrostatic)
    share = {"flowing": ngs.CF(1.0), "rest": ngs.CF(0.0),
             "front": ngs.IfPos(ngs.x - FRONT, ((ngs.x - FRONT) / FRONT) ** 2, 0.0)}
    velocity.Set(slump * share[state])
    solver.previous.vec.data = solver.solution.vec
    solver.scheme.begin_step(dt)
    picard = solver.nonlinear.picard_system
    picard.prepare()
    return solver, picard.assemble(), picard.f.vec


def measure(PETSc, state: str, size: float, eps: float, dt: float, variants: list[str],
            steps: int) -> list[dict]:
    import numpy as np
    from common.block_preconditioner import pressure_forms

    from granflow.fem.forms import ViscoplasticStress
    from granflow.fem.measure import SPACE

    solver, matrix, rhs = picard_system(state, size, eps, dt, None)
    space = solver.space
    free = np.array(list(space.FreeDofs()), dtype=bool)
    c0 = time.process_time()
    exact = rhs.CreateVector()
    exact.data = matrix.Inverse(space.FreeDofs(), inverse="umfpack") * rhs
    direct_cpu = time.process_time() - c0
    exact_free = exact.FV().NumPy()[free]

    stress = next(t for t in solver.terms if isinstance(t, ViscoplasticStress))
    m = stress.viscosity(*solver.solution.components)
    mass_form = pressure_forms(space.components[1], m, solver.terms, SPACE, "viscous")[0]
    mass_form.Assemble()
    split = space.Range(0).stop
    free_p = free[split:]
    mass = to_petsc(PETSc, mass_form.mat, free_p)
    a = to_petsc(PETSc, matrix, free)
    n_u = int(free[:split].sum())
    n = int(free.sum())
    is_u = PETSc.IS().createStride(n_u, 0, 1)
    is_p = PETSc.IS().createStride(n - n_u, n_u, 1)
    b = PETSc.Vec().createWithArray(rhs.FV().NumPy()[free].copy())
    direct_residual = b.duplicate()
    a.mult(PETSc.Vec().createWithArray(exact_free.copy()), direct_residual)
    direct_residual.aypx(-1.0, b)
    rows = []
    for variant in variants:
        ksp = PETSc.KSP().create()
        ksp.setOptionsPrefix(f"{variant.replace('-', '_')}_")
        ksp.setOperators(a)
        configure(ksp, variant, is_u, is_p, mass, steps)
        x = b.duplicate()
        x.set(0.0)
        c0 = c1 = time.process_time()
        try:
            ksp.setUp()
            c1 = time.process_time()
            ksp.solve(b, x)
            failure = None
        except PETSc.Error as error:
            failure = f"PETSc error {error.ierr}"
        c2 = time.process_time()
        reason = ksp.getConvergedReason()
        residual = b.duplicate()
        a.mult(x, residual)
        residual.aypx(-1.0, b)
        difference = float(np.linalg.norm(x.getArray() - exact_free)
                           / np.linalg.norm(exact_free))
        rows.append({"case": "column", "state": state, "size": size, "eps": eps, "dt": dt,
                     "variant": variant, **VARIANTS[variant],
                     "unknowns": space.ndof, "free_unknowns": n,
                     "converged": failure is None and reason > 0,
                     "reason": failure or int(reason),
                     "steps": ksp.getIterationNumber(),
                     "relative_difference": difference,
                     "relative_residual": residual.norm() / b.norm(),
                     "direct_relative_residual": direct_residual.norm() / b.norm(),
                     "cpu_s": {"direct": direct_cpu, "setup": c1 - c0, "solve": c2 - c1}})
        ksp.destroy()
    return rows


def schur_of(solver, form_space):
    """The Cahouet-Chabard forms at the solver's iterate (``fieldsplit_parts``)."""
    from granflow.fem.fieldsplit_parts import schur_forms
    from granflow.fem.forms import BackwardDifferenceInertia, Inertia, ViscoplasticStress

    stress = next(t for t in solver.terms if isinstance(t, ViscoplasticStress))
    inertia = next(t for t in solver.terms if isinstance(t, (Inertia, BackwardDifferenceInertia)))
    m = stress.viscosity(*solver.solution.components)
    return schur_forms(form_space, m, inertia.dt / inertia.density, solver.coordinates)


def measure_ranks(PETSc, state: str, size: float, eps: float, dt: float,
                  steps: int, comm, rigid_modes: bool = False,
                  variant: str = "selfp-gamg", scaled: bool = False,
                  tolerance: float = TOLERANCE, history_wanted: bool = False) -> dict:
    """A fieldsplit variant (granflow's ``FieldsplitSolve``) on the system distributed by
    NGSolve over the ranks of ``comm`` (None: one process), handed to PETSc by ngspetsc (a
    MATIS of the ranks' local matrices on the free dofs' global numbering, converted to
    MPIAIJ), against NGSolve's direct solve; with one process, the true relative residual
    and the distance to the direct solve after every GMRes step (``history``)."""
    import ngsolve as ngs
    import numpy as np

    from granflow.fem.fieldsplit import FieldsplitSolve

    ranks = 1 if comm is None else comm.size
    solver, matrix, rhs = picard_system(state, size, eps, dt, comm)
    space = solver.space
    form = solver.nonlinear.picard_system.a
    c0 = time.process_time()
    exact = rhs.CreateVector()
    exact.data = matrix.Inverse(space.FreeDofs(),
                                inverse="masterinverse" if ranks > 1 else "umfpack") * rhs
    direct_cpu = time.process_time() - c0

    c0 = time.process_time()
    schur = schur_of(solver, space) if VARIANTS[variant]["p"] == "shell" else None
    solve = FieldsplitSolve(form, space.FreeDofs(), near_null_space=rigid_modes,
                            max_steps=steps, variant=variant, scaled=scaled, schur=schur,
                            tolerance=tolerance)
    f0 = PETSc.Log.getFlops()
    solve.update()
    ksp = solve.ksp
    system = solve._system
    a = system.matrix(matrix)
    b = system.vector(rhs)
    history: list[list[float]] = []
    split = space.Range(0).stop
    free = np.array(list(space.FreeDofs()), dtype=bool)
    fields = (np.arange(len(free)) < split)[free]

    def apart(x) -> list[float]:
        """The velocity's and the pressure's relative distances to the direct solve."""
        got, want = x.getArray(), system.vector(exact).getArray()
        return [float(np.linalg.norm(got[f] - want[f]) / np.linalg.norm(want[f]))
                for f in (fields, ~fields)]

    def monitor(ksp, its, rnorm) -> None:
        x = solve.unscaled(ksp.buildSolution())
        r = b.duplicate()
        a.mult(x, r)
        r.aypx(-1.0, b)
        history.append([its, rnorm, r.norm() / b.norm(), *apart(x)])

    if comm is None and history_wanted:
        ksp.setMonitor(monitor)
    ksp.setUp()
    c2 = time.process_time()
    out = rhs.CreateVector()
    try:
        solve.solve(rhs, out)
        failure = None
    except Exception as error:            # LinearSolveFailed: keep the record
        failure = str(error)
    c3, flops = time.process_time(), PETSc.Log.getFlops() - f0
    reason, iterations = int(ksp.getConvergedReason()), ksp.getIterationNumber()
    if failure is not None:
        x = solve.unscaled(ksp.getSolution().copy())
        system.back(x, out)
    difference = rhs.CreateVector()
    difference.data = out - exact
    distance = ngs.Norm(difference) / ngs.Norm(exact)
    x = system.vector(out)
    r = b.duplicate()
    a.mult(x, r)
    r.aypx(-1.0, b)
    per_field = apart(x) if comm is None else []
    solution = ngs.GridFunction(space)
    solution.vec.data = out
    u, p = solution.components
    norms = [float(np.sqrt(ngs.Integrate(f * f, space.mesh))) for f in (u, p)]
    cpu = {"direct": direct_cpu, "convert_setup": c2 - c0, "solve": c3 - c2}
    per_rank = [cpu] if comm is None else comm.allgather(cpu)
    flops_per_rank = [flops] if comm is None else comm.allgather(flops)
    solve.reset()
    return {"case": "column", "state": state, "size": size, "eps": eps, "dt": dt,
            "variant": variant, **VARIANTS[variant], "ranks": ranks,
            "rigid_modes": rigid_modes, "scaled": scaled, "tolerance": tolerance,
            "unknowns": space.ndofglobal, "free_unknowns": a.getSize()[0],
            "rows_per_rank": [] if comm is None else comm.allgather(a.getLocalSize()[0]),
            "converged": reason > 0, "reason": reason, "steps": iterations,
            "relative_difference": distance,
            "velocity_pressure_difference": per_field,
            "true_relative_residual": r.norm() / b.norm(),
            "velocity_l2": norms[0], "pressure_l2": norms[1],
            "cpu_s_per_rank": per_rank, "petsc_flops_per_rank": flops_per_rank,
            "history": history}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--state", nargs="+", choices=["rest", "flowing", "front"],
                        default=["rest", "flowing", "front"])
    parser.add_argument("--size", type=float, nargs="+", default=[0.04, 0.02])
    parser.add_argument("--eps", type=float, default=1e-6)
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS))
    parser.add_argument("--max-steps", type=int, default=400)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/three_d_krylov"))
    parser.add_argument("--ranks", action="store_true",
                        help="selfp + GAMG on NGSolve's distributed system, through ngspetsc "
                             "(run under mpiexec; on one process: the reference)")
    parser.add_argument("--variant", choices=("selfp-gamg", "selfp-gamg-flexible",
                                              "lsc-gamg-flexible", "cahouet-chabard"),
                        default="selfp-gamg",
                        help="with --ranks: the variant (selfp-gamg-flexible: the Schur "
                             "complement by selfp; lsc-gamg-flexible: by LSC, granflow's "
                             "numerics.linear_solver = 'fieldsplit'); records "
                             "fieldsplit_ranks_flexible_*")
    parser.add_argument("--rigid-modes", action="store_true",
                        help="with --ranks: GAMG told the velocity's rigid-body modes "
                             "(granflow's solve); records fieldsplit_ranks_rigid_*")
    parser.add_argument("--scaled", action="store_true",
                        help="with --ranks: the system scaled by its diagonal "
                             "(granflow.fem.fieldsplit_parts.scaling); records *_scaled_*")
    parser.add_argument("--tolerance", type=float, default=TOLERANCE,
                        help="with --ranks and a flexible variant: FGMRes' true relative "
                             "residual; records *_tol<value>_* unless the default")
    parser.add_argument("--table", action="store_true",
                        help="print the table of the FGMRes variants' records in --out "
                             "(steps at 973 / 5,414 / 18,192 unknowns, largest distance)")
    parser.add_argument("--history", action="store_true",
                        help="with --ranks on one process: the true relative residual and "
                             "the distance to the direct solve after every step (the "
                             "processor times then include computing them)")
    args = parser.parse_args(argv)
    if args.table:
        print(table(args.out))
        ranges = {name: stopping(args.out, kind) for name, kind in TABLE_KINDS.items()}
        (args.out / "table.json").write_text(json.dumps(
            {"table": table(args.out), "within_1e-6": ranges}, indent=1) + "\n",
            encoding="utf-8")
        return 0
    PETSc = petsc()
    if PETSc is None:
        print("three_d_fieldsplit.py needs petsc4py (pip install petsc petsc4py); "
              "it is not installed here", file=sys.stderr)
        return 2
    import ngsolve as ngs
    ngs.SetNumThreads(1)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.ranks:
        return ranks_mode(PETSc, args)
    for size in args.size:
        for state in args.state:
            rows = measure(PETSc, state, size, args.eps, args.dt, args.variants,
                           args.max_steps)
            for row in rows:
                print(json.dumps({k: row[k] for k in (
                    "state", "unknowns", "variant", "converged", "reason", "steps",
                    "relative_difference", "relative_residual", "cpu_s")}), flush=True)
            name = f"fieldsplit_{state}_h{size:g}.json"
            (args.out / name).write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
    return 0


def ranks_mode(PETSc, args: argparse.Namespace) -> int:
    """``--ranks``: one record per size and state, written by rank 0."""
    from three_d_krylov import world

    try:
        import ngsPETSc  # noqa: F401
    except ImportError:
        print("three_d_fieldsplit.py --ranks needs ngspetsc (pip install ngspetsc); "
              "it is not installed here", file=sys.stderr)
        return 2
    comm = world()
    for size in args.size:
        for state in args.state:
            row = measure_ranks(PETSc, state, size, args.eps, args.dt, args.max_steps, comm,
                                args.rigid_modes, args.variant, args.scaled, args.tolerance,
                                args.history)
            if comm is None or comm.rank == 0:
                print(json.dumps({k: row[k] for k in (
                    "state", "ranks", "free_unknowns", "converged", "steps",
                    "relative_difference", "velocity_pressure_difference",
                    "true_relative_residual", "cpu_s_per_rank")}), flush=True)
                kind = "ranks" + {"selfp-gamg": "", "selfp-gamg-flexible": "_flexible"}.get(
                    args.variant, "_" + args.variant) + (
                    "_rigid" if args.rigid_modes else "") + (
                    "_scaled" if args.scaled else "") + (
                    "" if args.tolerance == TOLERANCE else f"_tol{args.tolerance:g}")
                name = f"fieldsplit_{kind}_{state}_h{size:g}_n{row['ranks']}.json"
                (args.out / name).write_text(json.dumps(row, indent=1) + "\n",
                                             encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
