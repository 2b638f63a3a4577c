"""Benchmark: an iterative, distributed solve of the 3D systems of (3.2), GMRes with a block
preconditioner of NGSolve's own parts (``common/block_preconditioner.py``: BDDC on the
velocity, the viscosity-weighted pressure mass plus the inertia's pressure Laplacian on
the pressure), against the direct solve (UMFPACK; NGSolve's ``masterinverse`` under MPI).

Run: python benchmarks/three_d_krylov.py [--case column] [--state flowing] [--eps 1e-1 1e-6]
         [--dt 1e-4] [--size 0.04] [--schur cahouet-chabard viscous] [--exact-velocity]
         [--out benchmarks/results/three_d_krylov]
     mpiexec -n 2 python benchmarks/three_d_krylov.py ...        (the same, distributed)

The system is one Picard iteration's (3.2) as granflow's flow solver builds it
(``fem/flow_factory.py``) with the walls' u.N = 0 held by the space
(``boundary.non_penetration = "strong"``; BDDC cannot be built with the penalty):
``column``, the rectangle-rigid scenario in half a 10 cm channel at mesh.size; ``plug``,
the 3D periodic layer of the plug flow (0.5 m x 0.5 m x 6 m box, dZ = 0.25 m). The iterate
the law and the friction read, with the hydrostatic pressure: ``rest`` (u = 0: the first
iterate of a run, every cell rigid, m = 2 eta + sqrt(2) mu [p]_+ / eps), ``flowing`` (the
column: a divergence-free slump of about 1 m/s, every cell sheared; the layer: its initial
shear profile), or ``front`` (the column: the slump beyond X = 0.1 m only, growing as
(X / 0.1 - 1)^2, rigid behind: the contrast between the rigid back and the flowing front
grows as 1 / eps, as in a collapse). For each
numerics.eps (the regularisation's viscosity contrast) and pressure block: the direct
solve and the set-up and GMRes of the preconditioned one (unrestarted, at most
--max-steps, relative preconditioned residual 1e-8), timed in processor seconds (summed
over the ranks) and wall seconds; the GMRes steps to 1e-4, 1e-6 and 1e-8; the final
distance to the direct solution; the effective viscosity's cell averages (least, largest).
``--exact-velocity`` replaces BDDC by an exact velocity block (the pressure block alone is
then judged). Rank 0 prints one line per case and writes one JSON file under --out. The
prediction is in benchmarks/results/three_d_krylov/PREDICTION.md.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import ngsolve as ngs
import numpy as np
from common.block_preconditioner import SCHURS, block_preconditioner, taylor_hood_vertex_wirebasket
from ngsolve.krylovspace import GMResSolver

from granflow.config import load_config
from granflow.fem import flow_factory
from granflow.fem.flow_factory import build_flow
from granflow.fem.forms import ViscoplasticStress
from granflow.fem.measure import SPACE
from granflow.geometry.labels import BED
from granflow.geometry.mesh3d import extruded_mesh, periodic_box_mesh
from granflow.scenarios.channel_setup import ChannelSetup
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.materials import run_materials

TOL = 1e-8
FRONT = 0.1       # "front": the column flows beyond this X (m), is rigid behind it
LEVELS = (1e-4, 1e-6, 1e-8)


def world():
    try:
        from mpi4py import MPI
    except ImportError:
        return None
    return MPI.COMM_WORLD if MPI.COMM_WORLD.size > 1 else None


def distribute(mesh_maker, comm) -> ngs.Mesh:
    """Rank 0's mesh, distributed over the ranks by NGSolve (rank 0 keeps no element)."""
    if comm is None:
        return mesh_maker()
    import netgen.meshing

    from granflow.fem.distributed_flow import _copy
    if comm.rank == 0:
        ngmesh = _copy(mesh_maker().ngmesh)
        ngmesh.Distribute(comm)
    else:
        ngmesh = netgen.meshing.Mesh.Receive(comm)
    return ngs.Mesh(ngmesh)


def system(case: str, eps: float, size: float, comm):
    """The flow solver of the case on its (distributed) mesh, and its initial state."""
    if case == "column":
        config = load_config("rectangle-rigid", [
            "geometry.dimension=3", "boundary.channel_width=0.1", f"mesh.size={size!r}",
            "boundary.non_penetration=strong", f"numerics.eps={eps!r}"])
        setup = ChannelSetup.of(config)
        mesh = distribute(lambda: extruded_mesh(setup.section, setup.span, setup.size), comm)
        spec, height = setup.flow, config.geometry.height
        slump = ngs.CF((ngs.x * ngs.z, 0.0, -0.5 * ngs.z * ngs.z)) / (0.2 * 0.14)
    else:
        config = load_config("plug-flow", ["geometry.dimension=3", "mesh.size=0.25",
                                           "geometry.length=0.5", f"numerics.eps={eps!r}"])
        geo = config.geometry
        mesh = distribute(lambda: periodic_box_mesh(geo.length, geo.length, geo.height,
                                                    config.mesh.size), comm)
        spec = flow_spec(config, run_materials(config),
                         Layout(SPACE, periodic=True, dirichlet=BED, rough=BED))
        height, base = geo.height, config.initial.plug_base
        slump = ngs.CF((ngs.IfPos(ngs.z - base, config.initial.shear_rate * (ngs.z - base),
                                  0.0), 0.0, 0.0))
    flow_factory.taylor_hood = taylor_hood_vertex_wirebasket     # BDDC's vertex coarse space
    solver = build_flow(mesh, spec)
    density, force = config.material.density, spec.terms.body_force
    return solver, slump, -density * force[2] * (height - ngs.z)


def measure(args: argparse.Namespace, eps: float, schur: str, comm) -> dict:
    ranks = 1 if comm is None else comm.size
    solver, slump, hydrostatic = system(args.case, eps, args.size, comm)
    space = solver.space
    velocity, pressure = solver.solution.components
    pressure.Set(hydrostatic)
    share = {"flowing": ngs.CF(1.0), "rest": ngs.CF(0.0),
             "front": ngs.IfPos(ngs.x - FRONT, ((ngs.x - FRONT) / FRONT) ** 2, 0.0)}
    velocity.Set(slump * share[args.state])
    solver.previous.vec.data = solver.solution.vec
    solver.scheme.begin_step(args.dt)
    stress = next(t for t in solver.terms if isinstance(t, ViscoplasticStress))
    pre = block_preconditioner(space, solver.terms, stress, solver.solution, SPACE, schur)
    picard = solver.nonlinear.picard_system
    picard.prepare()
    matrix = picard.assemble()
    rhs, free = picard.f.vec, space.FreeDofs()
    clock = Clock(comm)
    direct = "masterinverse" if ranks > 1 else "umfpack"
    exact = rhs.CreateVector()
    with clock("direct"):
        inverse = matrix.Inverse(free, inverse=direct)
        exact.data = inverse * rhs
    with clock("setup"):
        pre.update()
    operator = pre.mat
    if args.exact_velocity:
        eu, ep = space.Embedding(0), space.Embedding(1)
        inverse_u = pre.velocity_form.mat.Inverse(space.components[0].FreeDofs(), inverse=direct)
        operator = eu @ inverse_u @ eu.T + ep @ pre.pressure_mat() @ ep.T
    gmres = GMResSolver(matrix, operator, tol=TOL, maxiter=args.max_steps)
    out = rhs.CreateVector()
    with clock("gmres"):
        gmres.Solve(rhs, out, initialize=True)
    history = np.array(gmres.residuals) / gmres.residuals[0]
    reach = {f"{level:g}": (int(np.argmax(history < level)) + 1 if (history < level).any()
                            else None) for level in LEVELS}
    out.data -= exact
    cells = ngs.GridFunction(ngs.L2(space.mesh, order=0))
    cells.Set(pre.viscosity)
    values = cells.vec.FV().NumPy()
    low = space.mesh.comm.Min(float(values.min()) if len(values) else np.inf)
    high = space.mesh.comm.Max(float(values.max()) if len(values) else 0.0)
    return {"case": args.case, "state": args.state, "eps": eps, "dt": args.dt,
            "size": args.size, "schur": schur, "exact_velocity": args.exact_velocity,
            "ranks": ranks, "unknowns": space.ndofglobal,
            "viscosity_pa_s": [low, high], "contrast": high / low,
            "gmres_steps": gmres.iterations, "steps_to": reach,
            "floor": float(history.min()),
            "relative_error": ngs.Norm(out) / ngs.Norm(exact),
            "cpu_s": clock.cpu, "wall_s": clock.wall,
            "cpu_s_per_gmres_step": clock.cpu["gmres"] / max(gmres.iterations, 1)}


class Clock:
    """Processor seconds summed over the ranks and wall seconds (the slowest rank's)."""

    def __init__(self, comm) -> None:
        self.comm, self.cpu, self.wall = comm, {}, {}

    def __call__(self, name: str) -> Clock:
        self._name = name
        return self

    def __enter__(self) -> None:
        if self.comm is not None:
            self.comm.Barrier()
        self._c0, self._w0 = time.process_time(), time.perf_counter()

    def __exit__(self, *exc: object) -> None:
        cpu, wall = time.process_time() - self._c0, time.perf_counter() - self._w0
        if self.comm is not None:
            from mpi4py import MPI
            cpu, wall = self.comm.allreduce(cpu), self.comm.allreduce(wall, op=MPI.MAX)
        self.cpu[self._name], self.wall[self._name] = cpu, wall


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--case", choices=["column", "plug"], default="column")
    parser.add_argument("--state", choices=["rest", "flowing", "front"], default="flowing")
    parser.add_argument("--eps", type=float, nargs="+", default=[1e-1, 1e-2, 1e-3, 1e-4, 1e-6])
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--size", type=float, default=0.04)
    parser.add_argument("--schur", nargs="+", choices=SCHURS, default=list(SCHURS))
    parser.add_argument("--exact-velocity", action="store_true")
    parser.add_argument("--max-steps", type=int, default=400)
    parser.add_argument("--out", type=Path, default=Path("benchmarks/results/three_d_krylov"))
    args = parser.parse_args(argv)
    ngs.SetNumThreads(1)
    comm = world()
    rows = []
    for schur in args.schur:
        for eps in args.eps:
            row = measure(args, eps, schur, comm)
            rows.append(row)
            if comm is None or comm.rank == 0:
                print(json.dumps({k: row[k] for k in (
                    "case", "state", "eps", "schur", "ranks", "unknowns", "contrast",
                    "gmres_steps", "steps_to", "relative_error", "cpu_s", "wall_s")}),
                    flush=True)
    if comm is None or comm.rank == 0:
        args.out.mkdir(parents=True, exist_ok=True)
        mesh = f"_h{args.size:g}" if args.case == "column" else ""
        name = (f"{args.case}_{args.state}{mesh}_dt{args.dt:g}"
                f"{'_exactu' if args.exact_velocity else ''}_n{rows[0]['ranks']}.json")
        (args.out / name).write_text(json.dumps(rows, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
