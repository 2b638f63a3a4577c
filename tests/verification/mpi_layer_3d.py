"""Run by tests/verification/test_mpi.py under ``mpiexec -n N``: the 3D layer of the plug
flow for two coarse steps; rank 0 runs it and prints its results as one JSON line, the
other ranks serve its distributed solves (``fem/distributed_flow.py``)."""

import json

from granflow.config import load_config
from granflow.fem.distributed_flow import release, serve
from granflow.fem.mpi import world_rank, world_size
from granflow.scenarios.plug_flow_3d import build_plug_flow_3d

OVERRIDES = ["geometry.dimension=3", "time.dt=0.025", "mesh.size=0.25", "geometry.length=0.5",
             "time.output_times=[]", "time.t_end=0.05"]


def run() -> dict[str, float]:
    problem = build_plug_flow_3d(load_config("plug-flow", OVERRIDES))
    result = problem.simulation.run()
    u = problem.solver.velocity
    return {"status": result.status, "steps": result.steps, "ranks": world_size(),
            "error": problem.velocity_error(result.t_final),
            "kinetic_energy": problem.solver.kinetic_energy(),
            "speed_l2": problem.solver.coordinates.integrate(u * u, problem.mesh) ** 0.5,
            "unknowns": problem.solver.space.ndofglobal}


if __name__ == "__main__":
    if world_rank() > 0:
        serve()
    else:
        try:
            print(json.dumps(run()), flush=True)
        finally:
            release()
