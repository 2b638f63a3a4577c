"""The flow solver on one process, or with its solve distributed over MPI ranks.

Under ``mpiexec -n N granflow ...`` rank 0 runs the program as one process would: the mesh,
the ALE move, remeshing, every output and the checkpoint work on its whole (serial) mesh
and fields. Only the flow's nonlinear solve (3.2), the costly part, is done on a copy of
the mesh that NGSolve distributes over all ranks (``fem/mpi.py``; rank 0 holds no element
and gathers the matrix for the direct solver, the others assemble; PETSc's fieldsplit solve,
``fem/fieldsplit.py``, spreads its rows over all ranks instead). A fieldsplit solve that
fails, fails on every rank: rank 0's loop rejects the step, the others wait for its next
command. The other ranks serve
rank 0 (``serve``): they receive their part of the mesh, then before each solve the moved
vertices, the boundary labels (deposition changes them) and the mesh velocity, and
whenever rank 0's history changes (the start, a remesh, a restored checkpoint) the
history; they solve, accept and reject with rank 0. The solution is gathered back into rank
0's fields after each solve. Values travel by the serial mesh's numbering: each rank maps its
vertices to rank 0's by their coordinates (sent bit for bit), its edges by their vertices,
its degrees of freedom by their nodes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.fem.fieldsplit import FIELDSPLIT, LinearSolveFailed
from granflow.fem.flow import FlowSolver
from granflow.fem.flow_factory import build_flow
from granflow.fem.flow_spec import FlowSpec
from granflow.fem.linalg import MASTER_INVERSE
from granflow.fem.mpi import world_rank, world_size
from granflow.simulation.outcomes import IterationReport


def flow_solver(mesh: ngs.Mesh, spec: FlowSpec) -> Any:
    """The flow solver of ``spec`` on ``mesh``: on one process the factory's; under
    ``mpiexec`` rank 0's ``DistributedFlow`` (module docstring)."""
    serial = build_flow(mesh, spec)
    return serial if world_size() == 1 else DistributedFlow(serial, spec)


def _world() -> Any:
    from mpi4py import MPI  # only under mpiexec: mpi4py is an optional install

    return MPI.COMM_WORLD


class _Part:
    """This rank's share of the distributed solver: the flow solver on its part of the
    mesh and the maps of its vertices, faces and degrees of freedom to rank 0's. Every
    method is collective: rank 0 calls it after sending the command, the others on
    receiving it (``serve``)."""

    def __init__(self, spec: FlowSpec, serial: FlowSolver | None) -> None:
        import netgen.meshing

        comm = self.comm = _world()
        if serial is not None:
            ngmesh = _copy(serial.mesh.ngmesh)
            ngmesh.Distribute(comm)
        else:
            ngmesh = netgen.meshing.Mesh.Receive(comm)
        self.mesh = ngs.Mesh(ngmesh)
        self.solver = build_flow(self.mesh, spec)
        self._link(serial)

    def _link(self, serial: FlowSolver | None) -> None:
        """The maps to rank 0's numbering (module docstring)."""
        data = _numbering(serial) if serial is not None else None
        data = self.comm.bcast(data, root=0)
        mesh = self.mesh
        xyz = mesh.ngmesh.Coordinates()
        index = {row.tobytes(): k for k, row in enumerate(data["points"])}
        self.vertices = np.array([index[row.tobytes()] for row in xyz], dtype=np.int64)
        edges = {(int(a), int(b)): k for k, (a, b) in enumerate(data["edges"])}
        local_edges = [self._serial_edge(e, edges) for e in mesh.edges]
        self.dofs = _dof_map(self.solver.space, self.vertices, local_edges,
                             data["space_vertices"], data["space_edges"])
        self.w_dofs = _dof_map(self.solver.mesh_velocity.space, self.vertices, local_edges,
                               data["w_vertices"], data["w_edges"])
        faces = {tuple(face): k for k, face in enumerate(data["faces"])}
        local = mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1
        self.faces = np.array([faces[tuple(np.sort(self.vertices[f]))] for f in local],
                              dtype=np.int64)
        if len(self.faces) and tuple(mesh.GetBoundaries()) != tuple(data["boundaries"]):
            raise RuntimeError("a distributed mesh part numbers its boundaries otherwise")
        self.maps = self.comm.gather((self.dofs, self.w_dofs), root=0)

    def _serial_edge(self, edge: Any, edges: dict[tuple[int, int], int]) -> int:
        a, b = (int(self.vertices[v.nr]) for v in edge.vertices)
        return edges[(min(a, b), max(a, b))]

    # --- the commands --------------------------------------------------------------
    def solve(self, step: dict[str, Any]) -> tuple[IterationReport, np.ndarray | None]:
        """Take rank 0's vertices, labels and mesh velocity, solve the step, gather the
        solution (rank 0's numbering, on rank 0; None elsewhere)."""
        self.mesh.ngmesh.Coordinates()[:] = step["points"][self.vertices]
        if len(self.faces):
            self.mesh.ngmesh.Elements2D().NumPy()["index"][:] = step["labels"][self.faces]
        velocity = self.solver.mesh_velocity.vec
        velocity.FV().NumPy()[:] = _take(step["w"], self.w_dofs)
        report = self.solver.solve_step(step["dt"], step["tol"], step["max_iterations"],
                                        step["velocity_floor"])
        return report, self._gather(self.solver.solution.vec, step["size"])

    def _gather(self, vec: ngs.BaseVector, size: int) -> np.ndarray | None:
        vec.Cumulate()
        parts = self.comm.gather(vec.FV().NumPy().copy(), root=0)
        if parts is None:
            return None
        out = np.zeros(size)
        for (dofs, _), values in zip(self.maps, parts, strict=True):
            used = dofs >= 0
            out[dofs[used]] = values[used]
        return out

    def history(self, state: dict[str, Any]) -> None:
        """Rank 0's history (``FlowSolver.save_history``), each field in this part's
        numbering."""
        size = state["__size__"]
        local = {key: (_take(value, self.dofs) if isinstance(value, np.ndarray) and
                       len(value) == size else value)
                 for key, value in state.items() if key != "__size__"}
        self.solver.restore_history(local)

    def accept(self, dt: float | None) -> None:
        self.solver.accept(dt)

    def reject(self, _: object = None) -> None:
        self.solver.reject()

    def restart_history(self, _: object = None) -> None:
        self.solver.restart_history()


def _copy(ngmesh: Any) -> Any:
    """A copy of a Netgen mesh with its periodic identifications (``Copy()`` drops them)."""
    from netgen.meshing import IdentificationType

    out = ngmesh.Copy()
    for a, b, nr in ngmesh.GetIdentifications():
        out.AddPointIdentification(a, b, identnr=nr, type=IdentificationType.PERIODIC)
    return out


def _numbering(serial: FlowSolver) -> dict[str, Any]:
    """Rank 0's vertices, edges, faces and the degrees of freedom of its nodes."""
    mesh = serial.mesh
    edges = np.array([sorted(v.nr for v in e.vertices) for e in mesh.edges], dtype=np.int64)
    faces = np.sort(mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1,
                    axis=1)
    out: dict[str, Any] = {"points": mesh.ngmesh.Coordinates().copy(), "edges": edges,
                           "faces": faces, "boundaries": list(mesh.GetBoundaries())}
    for name, space in (("space", serial.space), ("w", serial.mesh_velocity.space)):
        out[f"{name}_vertices"] = _node_dofs(space, ngs.VERTEX, mesh.nv)
        out[f"{name}_edges"] = _node_dofs(space, ngs.EDGE, mesh.nedge)
    return out


def _node_dofs(space: ngs.FESpace, kind: Any, count: int) -> np.ndarray:
    """(count, k) the degrees of freedom of each node of this kind."""
    rows = [space.GetDofNrs(ngs.NodeId(kind, n)) for n in range(count)]
    return np.array(rows, dtype=np.int64).reshape(count, -1) if count else (
        np.empty((0, 0), dtype=np.int64))


def _dof_map(space: ngs.FESpace, vertices: np.ndarray, edges: list[int],
             serial_vertices: np.ndarray, serial_edges: np.ndarray) -> np.ndarray:
    """For each local degree of freedom, rank 0's (-1 for one of no node: a periodic
    space keeps the identified vertices' own degrees of freedom unused)."""
    out = np.full(space.ndof, -1, dtype=np.int64)
    if len(vertices):             # rank 0's part of a distributed mesh is empty
        out[_node_dofs(space, ngs.VERTEX, len(vertices))] = serial_vertices[vertices]
    if len(edges):
        out[_node_dofs(space, ngs.EDGE, len(edges))] = serial_edges[np.asarray(edges)]
    return out


def _take(values: np.ndarray, dofs: np.ndarray) -> np.ndarray:
    """Rank 0's values at this part's degrees of freedom; 0 at those of no node (a
    periodic space's unused copies at the identified vertices)."""
    out = values[np.maximum(dofs, 0)]
    out[dofs < 0] = 0.0
    return out


class DistributedFlow:
    """Rank 0's flow solver under MPI: the serial solver (what the outputs, the mover and
    the remesher read) with its solve done by all ranks (module docstring). Everything but
    stepping is the serial solver's."""

    def __init__(self, serial: FlowSolver, spec: FlowSpec) -> None:
        self.serial = serial
        if spec.solver.linear_solver != FIELDSPLIT:    # PETSc's solve is distributed itself
            spec = replace(spec, solver=replace(spec.solver, linear_solver=MASTER_INVERSE))
        _send("build", spec)
        self.part = _Part(spec, serial)

    def __getattr__(self, name: str) -> Any:
        return getattr(self.serial, name)

    def _share_history(self) -> None:
        state = self.serial.save_history() | {"__size__": self.serial.space.ndof}
        _send("history", state)
        self.part.history(state)

    def set_state(self, velocity: ngs.CoefficientFunction,
                  pressure: ngs.CoefficientFunction) -> None:
        self.serial.set_state(velocity, pressure)
        self._share_history()

    def restore_history(self, state: dict[str, object]) -> None:
        self.serial.restore_history(state)
        self._share_history()

    def inherit(self, old: Any, carry: Any) -> None:
        self.serial.inherit(getattr(old, "serial", old), carry)
        self.part.solver.nonlinear.carried_work = old.linear_work()
        self._share_history()

    def linear_work(self) -> dict[str, int]:
        """The counts of the solves done on the ranks (rank 0's share of them: PETSc's
        steps are collective, so every rank counts the same)."""
        return self.part.solver.linear_work()

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        serial = self.serial
        faces = serial.mesh.ngmesh.Elements2D().NumPy()["index"].copy()
        step = {"dt": dt, "tol": tol, "max_iterations": max_iterations,
                "velocity_floor": velocity_floor, "size": serial.space.ndof,
                "points": serial.mesh.ngmesh.Coordinates().copy(), "labels": faces,
                "w": serial.mesh_velocity.vec.FV().NumPy().copy()}
        _send("solve", step)
        report, solution = self.part.solve(step)
        serial.scheme.begin_step(dt)              # the step's coefficients, as solve_step's
        serial.nonlinear.prepare_norm()           # the norms of the local error, moved mesh
        assert solution is not None
        serial.solution.vec.FV().NumPy()[:] = solution
        return report

    def accept(self, dt: float | None = None) -> None:
        _send("accept", dt)
        self.part.accept(dt)
        self.serial.accept(dt)

    def reject(self) -> None:
        _send("reject", None)
        self.part.reject()
        self.serial.reject()

    def restart_history(self) -> None:
        _send("restart_history", None)
        self.part.restart_history()
        self.serial.restart_history()


def _send(command: str, payload: Any) -> None:
    """Rank 0 tells the serving ranks what to do next."""
    _world().bcast((command, payload), root=0)


def serve() -> None:
    """The loop of a rank other than 0: do what rank 0 sends until it says stop."""
    comm = _world()
    part: _Part | None = None
    while True:
        command, payload = comm.bcast(None, root=0)
        if command == "stop":
            return
        if command == "build":
            part = _Part(payload, None)
            continue
        assert part is not None
        action: Callable[[Any], Any] = getattr(part, command)
        try:
            action(payload)
        except LinearSolveFailed:   # on every rank at once: rank 0's loop rejects the step
            continue


def release() -> None:
    """Rank 0, at its end: the serving ranks stop (nothing on one process)."""
    if world_size() > 1 and world_rank() == 0:
        _send("stop", None)
