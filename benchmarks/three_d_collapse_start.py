"""Benchmark: the first steps of the 3D rectangle collapse from the pieces that exist (the
flow solver on tetrahedra, the prototype ALE move of ale/channel_mover.py), before the
column kind exists in 3D.

Run: python benchmarks/three_d_collapse_start.py [--size 0.02] [--steps 20] [--dt 2e-3]
         [--out benchmarks/results/three_d_collapse_start]

The rectangle of the rigid-bed collapse (l0 = 20 cm, h0 = 14 cm, Drucker-Prager 25.5 deg,
eta = 1 Pa s, eps = 1e-6) in half a 10 cm channel: Coulomb friction 25.5 deg on the bed,
10.2 deg on the back and side walls, the centre plane frictionless, all with the penalty
1e12; Picard (3.2) to 1e-4, UMFPACK (the cheapest in 3D, benchmarks/three_d_solvers.py);
fixed steps, the mesh moved by (3.6) with w(u^n), without or (``--conserve-volume``) with
the correction of its volume drift. Each row: the
time, the Picard iterations, the front's X, the volume's relative drift, processor
seconds. What it shows: the parts compose, what a step costs, and the volume drift of the
move without and with its correction. Writes JSON.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import ngsolve as ngs

from granflow.ale.channel_mover import ChannelMover, ChannelPlanes
from granflow.fem.flow_factory import (
    Discretisation,
    FlowSpec,
    GivenLaw,
    SolverChoice,
    Terms,
    build_flow,
)
from granflow.fem.forms import FrictionWall
from granflow.fem.measure import SPACE
from granflow.geometry.domains import column
from granflow.geometry.labels import BED, SIDE, SYMMETRY, WALL
from granflow.geometry.mesh3d import channel_column_mesh
from granflow.physics import CoulombFriction, DruckerPrager, gravity_vector_3d

RHO, CHANNEL, WIDTH, HEIGHT = 1550.0, 0.1, 0.2, 0.14


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, default=0.02)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--dt", type=float, default=2e-3)
    parser.add_argument("--conserve-volume", action="store_true",
                        help="correct the move's volume drift (ChannelMover)")
    parser.add_argument("--out", type=Path,
                        default=Path("benchmarks/results/three_d_collapse_start"))
    args = parser.parse_args(argv)
    ngs.SetNumThreads(1)
    mesh = channel_column_mesh(column("rectangle", WIDTH, HEIGHT), CHANNEL, args.size,
                               half=True)
    walls = [FrictionWall(label, CoulombFriction(angle, 1e-6)) for label, angle
             in ((BED, 25.5), (WALL, 10.2), (SIDE, 10.2), (SYMMETRY, 0.0))]
    force = gravity_vector_3d(9.81, 0.0)
    law = DruckerPrager(viscosity=1.0, friction_angle_deg=25.5, eps=1e-6)
    solver = build_flow(mesh, FlowSpec(GivenLaw(law, RHO),
                                       Terms(force, walls=tuple(walls), penalty=1e12),
                                       Discretisation(SPACE),
                                       SolverChoice("picard", linear_solver="umfpack")))
    solver.set_state(ngs.CF((0.0, 0.0, 0.0)), -RHO * force[2] * (HEIGHT - ngs.z))
    mover = ChannelMover(mesh, solver.previous.components[0], ChannelPlanes(CHANNEL, True),
                         conserve_volume=args.conserve_volume)
    volume0, t, rows = mover.volume(), 0.0, []
    start = time.process_time()
    for step in range(args.steps):
        if step and mover.move(args.dt) is not None:
            print("a tetrahedron inverted: stopped")
            break
        report = solver.solve_step(args.dt, 1e-4, 300)
        if not report.converged:
            print("Picard did not converge: stopped")
            break
        solver.accept(args.dt)
        t += args.dt
        rows.append({"t": t, "iterations": report.iterations,
                     "front_x": float(mesh.ngmesh.Coordinates()[:, 0].max()),
                     "volume_drift": mover.volume() / volume0 - 1.0,
                     "cpu_s": time.process_time() - start})
        r = rows[-1]
        print(f"t={t:.4f} its={r['iterations']:3d} front={r['front_x']:.5f} m "
              f"dV/V={r['volume_drift']:.2e} cpu={r['cpu_s']:.1f}s", flush=True)
    out = {"size": args.size, "dt": args.dt, "tetrahedra": mesh.ne,
           "conserve_volume": args.conserve_volume,
           "unknowns": solver.space.ndof, "rows": rows}
    args.out.mkdir(parents=True, exist_ok=True)
    tag = "_conserved" if args.conserve_volume else ""
    (args.out / f"start_h{args.size:g}{tag}.json").write_text(json.dumps(out, indent=1) + "\n",
                                                        encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
