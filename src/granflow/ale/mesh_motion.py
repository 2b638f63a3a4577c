"""Mesh velocities w^n (paper section 3.2) and the move of the mesh by dt w^n (3.1).

Each velocity solver has ``compute() -> GridFunction`` giving w from its source velocity on
the current mesh (``solve_again`` for another source on the same mesh); the forms are built
once and reassembled on the moved mesh.
"""

from __future__ import annotations

from typing import Protocol

import ngsolve as ngs
import numpy as np

from granflow.fem.linalg import ReusableLU
from granflow.geometry.mesh import BED, SURFACE, signed_areas
from granflow.simulation.outcomes import MoveFailure


def vertex_values(field: ngs.GridFunction) -> np.ndarray:
    """(nv, dim) vertex values of a P2 vector GridFunction (vertex dofs come first)."""
    nv = field.space.mesh.nv
    return np.column_stack([c.vec.FV().NumPy()[:nv] for c in field.components])


def move_mesh(mesh: ngs.Mesh, displacement: np.ndarray) -> None:
    """Apply the map (3.1) X -> X + dt w at the vertices, in place (straight edges)."""
    coords = mesh.ngmesh.Coordinates()
    coords += displacement


class _LinearMeshVelocity:
    """A linear problem for w^n assembled on the current mesh, its LU pattern reused."""

    def __init__(self, a: ngs.BilinearForm, f: ngs.LinearForm, solution: ngs.GridFunction,
                 solver: str = "umfpack") -> None:
        self._a, self._f, self._solution = a, f, solution
        self._lu = ReusableLU(a, a.space.FreeDofs(), solver)

    def compute(self) -> ngs.GridFunction:
        """Solve for w on the current mesh from the current velocity."""
        self._a.Assemble()
        self._lu.update()
        return self.solve_again()

    def forget_factorisation(self) -> None:
        """The next ``compute`` factorises afresh (symbolic analysis included)."""
        self._lu.reset()

    def solve_again(self) -> ngs.GridFunction:
        """Solve for another source velocity on the same mesh (the LU is reused)."""
        self._f.Assemble()
        self._lu.solve(self._f.vec, self._solution.vec)
        return self._store()

    def _store(self) -> ngs.GridFunction:
        return self._solution


class VerticalMeshVelocity(_LinearMeshVelocity):
    """w = (0, w) with w = 0 on the bed and w N_z = u.N on the surface (Table 2 set-up).

    The kinematic condition (2.12) is imposed with the boundary penalty of (3.6); the
    interior is a harmonic extension, periodic in x like the flow.
    """

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                 target: ngs.GridFunction, penalty: float, periodic: bool = True,
                 solver: str = "umfpack") -> None:
        space = ngs.H1(mesh, order=2, dirichlet=BED)
        if periodic:
            space = ngs.Periodic(space)
        w, v = space.TnT()
        n = ngs.specialcf.normal(2)
        surface = ngs.ds(definedon=mesh.Boundaries(SURFACE))
        a = ngs.BilinearForm(space)
        a += ngs.grad(w) * ngs.grad(v) * ngs.dx
        a += penalty * (w * n[1]) * (v * n[1]) * surface
        f = ngs.LinearForm(space)
        f += penalty * (velocity * n) * (v * n[1]) * surface
        super().__init__(a, f, ngs.GridFunction(space), solver)
        self._target = target

    def _store(self) -> ngs.GridFunction:
        self._target.Set(ngs.CF((0.0, self._solution)))
        return self._target


class ElasticMeshVelocity(_LinearMeshVelocity):
    """(3.6): int Dw:Dv + xi int_Gamma (w.N - u.N)(v.N) = 0 (boundary penalty).

    The system is symmetric positive definite, so it is factorised by sparse Cholesky
    whatever ``solver`` says: at 20,000 triangles it takes 74 MB against 242 MB for
    PARDISO's LU, at the same speed (benchmarks/scaling.py, peak memory).
    """

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                 target: ngs.GridFunction, penalty: float, solver: str = "umfpack") -> None:
        w, v = target.space.TnT()
        n = ngs.specialcf.normal(mesh.dim)
        a = ngs.BilinearForm(target.space, symmetric=True)
        a += ngs.InnerProduct(ngs.Sym(ngs.Grad(w)), ngs.Sym(ngs.Grad(v))) * ngs.dx
        a += penalty * (w * n) * (v * n) * ngs.ds
        f = ngs.LinearForm(target.space)
        f += penalty * (velocity * n) * (v * n) * ngs.ds
        super().__init__(a, f, target, "sparsecholesky")


class LagrangeMeshVelocity(_LinearMeshVelocity):
    """(3.7): the normal condition through a P2 multiplier, which lets surface nodes slide.

    int Dw:Dv + xi^-1 int p q + int_Gamma q (w - u).N + int_Gamma p (v.N) = 0.
    """

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                 target: ngs.GridFunction, penalty: float, solver: str = "umfpack") -> None:
        space = target.space * ngs.H1(mesh, order=2)
        (w, p), (v, q) = space.TnT()
        n = ngs.specialcf.normal(mesh.dim)
        a = ngs.BilinearForm(space)
        a += ngs.InnerProduct(ngs.Sym(ngs.Grad(w)), ngs.Sym(ngs.Grad(v))) * ngs.dx
        a += (1.0 / penalty) * p * q * ngs.dx
        a += (q * (w * n) + p * (v * n)) * ngs.ds
        f = ngs.LinearForm(space)
        f += q * (velocity * n) * ngs.ds
        super().__init__(a, f, ngs.GridFunction(space), solver)
        self._target = target

    def _store(self) -> ngs.GridFunction:
        self._target.vec.data = self._solution.components[0].vec
        return self._target


class VelocityHistory(Protocol):
    """The flow state a mover reads: u^n, u^{n-1} (carried by the nodes) and t^n - t^{n-1}."""

    previous: ngs.GridFunction
    before_previous: ngs.GridFunction
    dt_previous: float


class AleMover:
    """Moves the mesh by dt w each step (3.1), checks it, and can undo the move.

    The mesh-velocity solver reads ``source``. With ``extrapolate`` off, w = w(u^n), the
    paper's (3.6)/(3.7). With it on, w = w(u^n + dt/2 (u^n - u^{n-1}) / dt_{n-1}), the mesh
    velocity of the extrapolated mid-step velocity: the domain then moves with second-order
    accuracy in time instead of first (an explicit Euler update in the positions), at the
    cost of one more back-substitution per step. w is linear in its source, so both parts
    are computed once per step and combined for whatever dt the step finally takes.
    """

    def __init__(self, mesh: ngs.Mesh, velocity_solver: MeshVelocitySolver,
                 source: ngs.GridFunction, flow: VelocityHistory,
                 target: ngs.GridFunction, extrapolate: bool = False) -> None:
        self.mesh = mesh
        self.velocity_solver = velocity_solver
        self.source, self.flow, self.target = source, flow, target
        self.extrapolate = extrapolate
        self.w_vertices: np.ndarray | None = None
        self._parts: tuple[ngs.BaseVector, ngs.BaseVector | None] | None = None
        self._saved: np.ndarray | None = None
        self.velocity_solves = 0

    def _velocity(self) -> ngs.GridFunction:
        return self.flow.previous.components[0]

    def _rate(self) -> ngs.BaseVector | None:
        """(u^n - u^{n-1}) / dt_{n-1}, or None without history or extrapolation."""
        if not self.extrapolate or self.flow.dt_previous <= 0:
            return None
        rate = self.source.vec.CreateVector()
        rate.data = self._velocity().vec - self.flow.before_previous.components[0].vec
        rate.data *= 1.0 / self.flow.dt_previous
        return rate

    def _compute_parts(self) -> None:
        self.source.vec.data = self._velocity().vec
        base = self.velocity_solver.compute().vec.CreateVector()
        base.data = self.target.vec
        self.velocity_solves += 1
        rate = self._rate()
        if rate is not None:
            self.source.vec.data = rate
            slope = self.velocity_solver.solve_again().vec.CreateVector()
            slope.data = self.target.vec
            self.velocity_solves += 1
            self._parts = (base, slope)
        else:
            self._parts = (base, None)

    def source_at_vertices(self, dt: float) -> np.ndarray:
        """The velocity the mesh follows where it is pure Lagrangian (at the vertices)."""
        values = vertex_values(self._velocity())
        rate = self._rate()
        if rate is not None:
            self.source.vec.data = rate
            values = values + 0.5 * dt * vertex_values(self.source)
        return values

    def prepare(self, dt: float) -> float:
        """w for a step of size dt (the parts are solved once per step)."""
        if self._parts is None:
            self._compute_parts()
        assert self._parts is not None
        base, slope = self._parts
        self.target.vec.data = base
        if slope is not None:
            self.target.vec.data += 0.5 * dt * slope
        self.w_vertices = vertex_values(self.target)
        return dt

    def move(self, dt: float) -> None:
        assert self.w_vertices is not None
        self._saved = self.mesh.ngmesh.Coordinates().copy()
        move_mesh(self.mesh, dt * self.w_vertices)

    def check(self) -> MoveFailure | None:
        if np.any(signed_areas(self.mesh) <= 0):
            return MoveFailure.INVERTED
        return None

    def undo(self) -> None:
        if self._saved is not None:
            self.mesh.ngmesh.Coordinates()[:] = self._saved

    def forcing_jumped(self) -> bool:
        """Whether the last move switched a boundary forcing on or off (none here)."""
        return False

    def after_accept(self) -> None:
        self.w_vertices = None
        self._parts = None
        self._saved = None


MeshVelocitySolver = VerticalMeshVelocity | ElasticMeshVelocity | LagrangeMeshVelocity
