"""Benchmark: the linear solver of the 3D collapse's Picard iteration (3.2), serial and on
NGSolve's MPI.

Run: python benchmarks/three_d_solvers.py [--sizes 0.04 0.028 0.02] [--solvers lu bddc]
     mpiexec -n 2 python benchmarks/three_d_solvers.py --solvers master bddc

The system: the rectangle of the rigid-bed collapse (l0 = 20 cm, h0 = 14 cm) extruded across
half a 10 cm channel (symmetry plane at the centre), Taylor-Hood P2/P1 tetrahedra, the
regularised Drucker-Prager law (2.13), implicit Euler inertia (dt = 1e-3 s) and ALE
convection by u - w (w = 0), Coulomb friction with the normal penalty (2.7), (2.8) on the
bed, the back wall and the side wall, the symmetry plane frictionless with the penalty. On
the MPI ranks rank 0 meshes and NGSolve distributes the mesh. From the hydrostatic
pressure and a divergence-free slump of about 1 m/s as the first iterate, three Picard
iterations (non-symmetric: convection by the iterate; the law flowing where it shears, rigid
where it does not); each iteration is assembled and solved by one solver:

- ``lu``: sparse LU of the whole system as granflow's runs factorise it (``fem/linalg.py``:
  PARDISO with MKL, no iterative refinement), one process; ``umfpack``: UMFPACK;
- ``master``: NGSolve's "masterinverse": the distributed matrix gathered on rank 0 and
  factorised there by NGSolve's default direct solver (PARDISO with MKL, NGSolve's default
  settings); ``master-umfpack``: the same with UMFPACK on rank 0;
- ``bddc``: NGSolve's BDDC preconditioner of the whole system (its wirebasket system
  factorised by UMFPACK, not the default Cholesky, which reads one triangle of a
  non-symmetric matrix) inside restarted GMRes to a relative residual of ``--rtol``. For
  P2 in 3D NGSolve's wirebasket holds the vertex and the edge dofs, i.e. every dof: the
  "preconditioner" is then the exact inverse;
- ``petsc-lu``, ``petsc-ilu``, ``petsc-asm``, ``petsc-gamg`` (one process; needs petsc4py,
  which the package index has as source only): PETSc's own sparse LU, or GMRes with ILU(0),
  additive Schwarz or PETSc's algebraic multigrid, on the same matrix (the factorisation or
  preconditioner's set-up counted in the solve);
- ``bddc-vertex``: the same with the wirebasket of the vertices only (``wb_withedges =
  False``): the edge dofs are eliminated element by element, a two-level method. With the
  penalty (2.7) its boundary blocks are singular, so here u.N = 0 is imposed strongly on
  the planes (they are normal to the axes) and the Coulomb friction, left out of the
  preconditioner for the same reason, is added to the matrix GMRes sees.

Each row: the unknowns, the time of assembly, of setting up the solver (factorisation or
preconditioner) and of the solve (processor seconds, summed over the ranks, and wall
seconds), the Krylov iterations, the peak resident memory (summed and largest rank), and
the last iterate's relative L2 distance to the ``lu`` one (``--reference`` JSON) or the
relative residual. Prints a table and writes JSON under --out (one file per solver and
rank count). The prediction is in benchmarks/results/three_d_solvers/PREDICTION.md.
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np
from mpi4py import MPI

from granflow.fem.forms import (
    CoulombWallFriction,
    FrictionWall,
    Inertia,
    NormalPenalty,
    Symbols,
    momentum_terms,
)
from granflow.fem.linalg import ReusableLU, direct_solver
from granflow.fem.measure import SPACE
from granflow.geometry.domains import column
from granflow.geometry.labels import BED, SIDE, SYMMETRY, WALL
from granflow.geometry.mesh3d import channel_column_mesh
from granflow.physics import CoulombFriction, DruckerPrager, gravity_vector_3d

COMM = MPI.COMM_WORLD
RHO, ETA, DELTA, BED_DEG, WALL_DEG, SIDE_DEG = 1550.0, 1.0, 25.5, 25.5, 10.2, 10.2
EPS, EPS_F, PENALTY, DT, CHANNEL = 1e-6, 1e-6, 1e12, 1e-3, 0.1
MAX_KRYLOV = 600     # GMRes steps (unrestarted) before a Krylov solve is given up


def distributed_mesh(size: float) -> ngs.Mesh:
    """Rank 0 meshes the half channel and, on several ranks, NGSolve distributes it."""
    if COMM.rank == 0:
        ngmesh = channel_column_mesh(column("rectangle", 0.2, 0.14), CHANNEL, size,
                                     half=True).ngmesh
        if COMM.size > 1:
            ngmesh.Distribute(COMM)
    else:
        import netgen.meshing
        ngmesh = netgen.meshing.Mesh.Receive(COMM)
    return ngs.Mesh(ngmesh)


def system(mesh: ngs.Mesh, solver: str):
    """Space, matrix forms (the preconditioner registered with the first), right-hand side
    and the iterate the coefficients read. The second form, empty but for ``bddc-vertex``,
    holds the wall friction apart from the preconditioned one (whose boundary blocks BDDC
    would have to invert: singular)."""
    # P2 in 3D: NGSolve puts the edge dofs in BDDC's wirebasket by default (then BDDC's
    # coarse system is the whole matrix, a direct solve); "bddc-vertex" keeps the vertices
    # and imposes u.N = 0 strongly on the planes (the penalty's blocks would be singular)
    strong = solver == "bddc-vertex"
    planes = ({"dirichletx": WALL, "dirichlety": f"{SIDE}|{SYMMETRY}", "dirichletz": BED}
              if strong else {})
    velocity = ngs.VectorH1(mesh, order=2, wb_withedges=not strong, **planes)
    space = velocity * ngs.H1(mesh, order=1)
    iterate, previous = ngs.GridFunction(space), ngs.GridFunction(space)
    force = gravity_vector_3d(9.81, 0.0)
    previous.components[1].Set(-RHO * force[2] * (0.14 - ngs.z))      # hydrostatic
    iterate.vec.data = previous.vec
    # a divergence-free slump of about 1 m/s as the first iterate: strain rates of a few
    # 1/s, so that the law and the convection are those of a flowing column
    iterate.components[0].Set(ngs.CF((ngs.x * ngs.z, 0.0, -0.5 * ngs.z * ngs.z))
                              / (0.2 * 0.14))
    dt = ngs.Parameter(DT)
    law = DruckerPrager(viscosity=ETA, friction_angle_deg=DELTA, eps=EPS)
    walls = [FrictionWall(label, CoulombFriction(angle, EPS_F)) for label, angle
             in ((BED, BED_DEG), (WALL, WALL_DEG), (SIDE, SIDE_DEG))]
    w = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
    penalty = 0.0 if strong else PENALTY
    terms = momentum_terms(density=RHO, inertia=Inertia(RHO, dt, previous.components[0]),
                           mesh_velocity=w, rheology=law, body_force=force, walls=walls,
                           penalty=penalty, coords=SPACE)
    terms = [t for t in terms if not (strong and isinstance(t, NormalPenalty))]
    if not strong:
        terms.append(NormalPenalty(SYMMETRY, PENALTY))
    (u, p), (v, q) = space.TnT()
    u_lin, p_lin = iterate.components
    s = Symbols(u=u, p=p, v=v, q=q, u_lin=u_lin, p_lin=p_lin, coords=SPACE)
    a, b, f = ngs.BilinearForm(space), ngs.BilinearForm(space), ngs.LinearForm(space)
    for term in terms:
        if (lhs := term.lhs(s, mesh)) is not None:
            if strong and isinstance(term, CoulombWallFriction):
                b += lhs
            else:
                a += lhs if isinstance(term, CoulombWallFriction) else lhs.Compile()
        if (rhs := term.rhs(s, mesh)) is not None:
            f += rhs
    pre = (ngs.Preconditioner(a, "bddc", inverse="umfpack") if solver.startswith("bddc")
           else None)
    return space, (a, b), f, iterate, pre


def direct(a: ngs.BilinearForm, freedofs: ngs.BitArray, solver: str) -> ngs.BaseMatrix | None:
    """A fresh factorisation of ``a.mat`` for the direct solvers (None for BDDC)."""
    if solver in ("lu", "umfpack"):
        lu = ReusableLU(a, freedofs, direct_solver("auto") if solver == "lu" else "umfpack")
        lu.update()
        return lu._inverse
    if solver.startswith("master"):
        if solver == "master-umfpack":        # the master factorises with UMFPACK
            a.mat.local_mat.SetInverseType("umfpack")
        return a.mat.Inverse(freedofs, inverse="masterinverse")
    return None


PETSC_PCS = {"petsc-lu": "lu", "petsc-ilu": "ilu", "petsc-asm": "asm", "petsc-gamg": "gamg"}


def petsc_solve(a: ngs.BilinearForm, f: ngs.LinearForm, freedofs: ngs.BitArray,
                out: ngs.BaseVector, solver: str, rtol: float) -> int:
    """The free dofs' system through petsc4py (one process): PETSc's own LU, or GMRes
    (unrestarted, MAX_KRYLOV steps) with ILU(0), ASM or GAMG. Its Krylov iterations."""
    import scipy.sparse as sp
    from petsc4py import PETSc

    free = np.array(list(freedofs), dtype=bool)
    rows, cols, vals = a.mat.COO()
    matrix = sp.csr_matrix((np.asarray(vals), (np.asarray(rows), np.asarray(cols))),
                           shape=a.mat.shape)[free][:, free]
    mat = PETSc.Mat().createAIJ(size=matrix.shape, csr=(
        matrix.indptr.astype(PETSc.IntType), matrix.indices.astype(PETSc.IntType),
        matrix.data))
    mat.assemble()
    ksp = PETSc.KSP().create()
    ksp.setOperators(mat)
    if solver == "petsc-lu":
        ksp.setType("preonly")
    else:
        ksp.setType("gmres")
        ksp.setGMRESRestart(MAX_KRYLOV)
        ksp.setTolerances(rtol=rtol, max_it=MAX_KRYLOV)
    ksp.getPC().setType(PETSC_PCS[solver])
    if solver != "petsc-gamg":    # PETSc's factorisations do not pivot: the zero pressure
        ksp.getPC().setFactorOrdering(nzdiag=1e-12)  # block needs rows reordered first
    rhs = PETSc.Vec().createWithArray(f.vec.FV().NumPy()[free].copy())
    x = rhs.duplicate()
    ksp.solve(rhs, x)
    values = out.FV().NumPy()
    values[:] = 0.0
    values[free] = x.getArray()
    return ksp.getIterationNumber()


def peak_memory_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def run(size: float, solver: str, rtol: float, iterations: int) -> dict:
    """Three Picard iterations with one solver; the row of measurements."""
    cpu0, wall0 = time.process_time(), time.perf_counter()
    mesh = distributed_mesh(size)
    space, (a, b), f, iterate, pre = system(mesh, solver)
    times = {"mesh_and_forms": time.process_time() - cpu0, "assemble": 0.0, "setup": 0.0,
             "solve": 0.0}
    walls = dict.fromkeys(times, 0.0)
    walls["mesh_and_forms"] = time.perf_counter() - wall0
    krylov, residual = [], 0.0
    freedofs = space.FreeDofs()
    for _ in range(iterations):
        for name, action in (("assemble", lambda: (a.Assemble(), b.Assemble(),
                                                   f.Assemble())),
                             ("setup", lambda: None), ("solve", None)):
            c0, w0 = time.process_time(), time.perf_counter()
            if name == "assemble":
                action()
            elif name == "setup":
                matrix = a.mat if solver != "bddc-vertex" else a.mat + b.mat
                inverse = direct(a, freedofs, solver)
            else:
                if solver in PETSC_PCS:
                    krylov.append(petsc_solve(a, f, freedofs, iterate.vec, solver, rtol))
                elif inverse is not None:
                    iterate.vec.data = inverse * f.vec
                    krylov.append(0)
                else:
                    gmres = ngs.solvers.GMResSolver(matrix, pre.mat, tol=rtol,
                                                    maxiter=MAX_KRYLOV, printrates=False)
                    iterate.vec.data = gmres * f.vec
                    krylov.append(gmres.iterations)
            times[name] += time.process_time() - c0
            walls[name] += time.perf_counter() - w0
    r = f.vec.CreateVector()
    r.data = f.vec - matrix * iterate.vec
    fixed = ~np.array(list(freedofs), dtype=bool)    # the planes' rows of bddc-vertex
    load = f.vec.CreateVector()
    load.data = f.vec
    for vec in (r, load):
        vec.FV().NumPy()[fixed] = 0.0
    residual = ngs.Norm(r) / ngs.Norm(load)
    u = iterate.components[0]
    row = {"solver": solver, "ranks": COMM.size, "size": size, "tetrahedra": COMM.allreduce(
        mesh.ne), "unknowns": space.ndofglobal, "krylov_iterations": krylov,
        "relative_residual": residual,
        "cpu_s": {k: COMM.allreduce(v) for k, v in times.items()},
        "wall_s": {k: COMM.allreduce(v, op=MPI.MAX) for k, v in walls.items()},
        "peak_memory_mb_sum": COMM.allreduce(peak_memory_mb()),
        "peak_memory_mb_max": COMM.allreduce(peak_memory_mb(), op=MPI.MAX),
        "velocity_l2": ngs.sqrt(ngs.Integrate(u * u, mesh)),
        "front_speed": _probe(mesh, u)}
    return row


def _probe(mesh: ngs.Mesh, u: ngs.CoefficientFunction) -> float:
    """u_x at the column's top front corner region (a point value, on whichever rank holds
    it): the solvers must agree on it."""
    point = (0.19, 0.02, 0.13)
    value = 0.0
    if mesh.ne > 0 and mesh.Contains(*point):
        value = float(u(mesh(*point))[0])
    return COMM.allreduce(value, op=MPI.MAX)


def finite(value: object) -> object:
    """``value`` with NaN (a broken-down solve's residual and probe) as null, for JSON."""
    if isinstance(value, float) and value != value:
        return None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [finite(v) for v in value]
    return value


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[0.04, 0.028, 0.02])
    parser.add_argument("--solvers", nargs="+", default=["lu", "bddc"],
                        choices=["lu", "umfpack", "master", "master-umfpack", "bddc",
                                 "bddc-vertex", *PETSC_PCS])
    parser.add_argument("--iterations", type=int, default=3)
    parser.add_argument("--rtol", type=float, default=1e-8)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/three_d_solvers"))
    args = parser.parse_args(argv)
    ngs.SetNumThreads(1)
    rows = []
    for size in args.sizes:
        for solver in args.solvers:
            if (solver in ("lu", "umfpack") or solver in PETSC_PCS) and COMM.size > 1:
                continue
            try:
                row = run(size, solver, args.rtol, args.iterations)
            except Exception as exc:   # NGSolve's: a singular block, a failed factorisation
                if COMM.size > 1:
                    raise
                rows.append({"solver": solver, "ranks": 1, "size": size, "failed": str(exc)})
                print(f"h={size:<6g} {solver:7s} failed: {exc}", flush=True)
                continue
            rows.append(row)
            if COMM.rank == 0:
                cpu, wall = row["cpu_s"], row["wall_s"]
                print(f"h={size:<6g} {solver:7s} ranks={row['ranks']} tets={row['tetrahedra']:6d} "
                      f"dofs={row['unknowns']:7d} assemble={cpu['assemble']:7.2f}s "
                      f"setup={cpu['setup']:7.2f}s solve={cpu['solve']:7.2f}s "
                      f"(wall {wall['setup'] + wall['solve']:7.2f}s) "
                      f"krylov={row['krylov_iterations']} res={row['relative_residual']:.1e} "
                      f"mem={row['peak_memory_mb_sum']:.0f}MB u_front={row['front_speed']:.6g}",
                      flush=True)
    if COMM.rank == 0:
        args.out.mkdir(parents=True, exist_ok=True)
        name = f"{'-'.join(args.solvers)}_ranks{COMM.size}.json"
        (args.out / name).write_text(json.dumps(finite(rows), indent=1) + "\n",
                                     encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
