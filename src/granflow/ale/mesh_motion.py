"""Mesh velocities w^n (paper section 3.2) and the move of the mesh by dt w^n (3.1).

Each velocity solver has ``compute() -> GridFunction`` giving w^n from u^n on the current
mesh; the forms are built once and reassembled on the moved mesh.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.geometry.mesh import BED, SURFACE, signed_areas


def vertex_values(field: ngs.GridFunction) -> np.ndarray:
    """(nv, 2) vertex values of a P2 vector GridFunction (vertex dofs come first)."""
    nv = field.space.mesh.nv
    return np.column_stack([c.vec.FV().NumPy()[:nv] for c in field.components])


def move_mesh(mesh: ngs.Mesh, displacement: np.ndarray) -> None:
    """Apply the map (3.1) X -> X + dt w at the vertices, in place (straight edges)."""
    coords = mesh.ngmesh.Coordinates()
    coords += displacement


class VerticalMeshVelocity:
    """w = (0, w) with w = 0 on the bed and w N_z = u.N on the surface (Table 2 set-up).

    The kinematic condition (2.12) is imposed with the boundary penalty of (3.6); the
    interior is a harmonic extension, periodic in x like the flow.
    """

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                 target: ngs.GridFunction, penalty: float, periodic: bool = True) -> None:
        space = ngs.H1(mesh, order=2, dirichlet=BED)
        if periodic:
            space = ngs.Periodic(space)
        w, v = space.TnT()
        n = ngs.specialcf.normal(2)
        surface = ngs.ds(definedon=mesh.Boundaries(SURFACE))
        self._a = ngs.BilinearForm(space)
        self._a += ngs.grad(w) * ngs.grad(v) * ngs.dx
        self._a += penalty * (w * n[1]) * (v * n[1]) * surface
        self._f = ngs.LinearForm(space)
        self._f += penalty * (velocity * n) * (v * n[1]) * surface
        self._w = ngs.GridFunction(space)
        self._target = target
        self._freedofs = space.FreeDofs()

    def compute(self) -> ngs.GridFunction:
        """Solve for w on the current mesh from the current velocity; store it in ``target``."""
        self._a.Assemble()
        self._f.Assemble()
        self._w.vec.data = self._a.mat.Inverse(self._freedofs, inverse="umfpack") * self._f.vec
        self._target.Set(ngs.CF((0.0, self._w)))
        return self._target


class ElasticMeshVelocity:
    """(3.6): int Dw:Dv + xi int_Gamma (w.N - u.N)(v.N) = 0 (boundary penalty)."""

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                 target: ngs.GridFunction, penalty: float) -> None:
        space = target.space
        w, v = space.TnT()
        n = ngs.specialcf.normal(2)
        self._a = ngs.BilinearForm(space)
        self._a += ngs.InnerProduct(ngs.Sym(ngs.Grad(w)), ngs.Sym(ngs.Grad(v))) * ngs.dx
        self._a += penalty * (w * n) * (v * n) * ngs.ds
        self._f = ngs.LinearForm(space)
        self._f += penalty * (velocity * n) * (v * n) * ngs.ds
        self._target = target
        self._inverse = None

    def compute(self) -> ngs.GridFunction:
        self._a.Assemble()
        self._f.Assemble()
        if self._inverse is None:
            self._inverse = self._a.mat.Inverse(inverse="umfpack")
        else:
            self._inverse.Update()
        self._target.vec.data = self._inverse * self._f.vec
        return self._target


class LagrangeMeshVelocity:
    """(3.7): the normal condition through a P2 multiplier, which lets surface nodes slide.

    int Dw:Dv + xi^-1 int p q + int_Gamma q (w - u).N + int_Gamma p (v.N) = 0.
    """

    def __init__(self, mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                 target: ngs.GridFunction, penalty: float) -> None:
        space = target.space * ngs.H1(mesh, order=2)
        (w, p), (v, q) = space.TnT()
        n = ngs.specialcf.normal(2)
        self._a = ngs.BilinearForm(space)
        self._a += ngs.InnerProduct(ngs.Sym(ngs.Grad(w)), ngs.Sym(ngs.Grad(v))) * ngs.dx
        self._a += (1.0 / penalty) * p * q * ngs.dx
        self._a += (q * (w * n) + p * (v * n)) * ngs.ds
        self._f = ngs.LinearForm(space)
        self._f += q * (velocity * n) * ngs.ds
        self._solution = ngs.GridFunction(space)
        self._target = target
        self._inverse = None

    def compute(self) -> ngs.GridFunction:
        self._a.Assemble()
        self._f.Assemble()
        if self._inverse is None:
            self._inverse = self._a.mat.Inverse(inverse="umfpack")
        else:
            self._inverse.Update()
        self._solution.vec.data = self._inverse * self._f.vec
        self._target.vec.data = self._solution.components[0].vec
        return self._target


class AleMover:
    """Moves the mesh by dt w^n each step (3.1), checks it, and can undo the move.

    w^n is computed once per time step (a rejected attempt reuses it with a smaller dt).
    """

    def __init__(self, mesh: ngs.Mesh, velocity_solver: MeshVelocitySolver) -> None:
        self.mesh = mesh
        self.velocity_solver = velocity_solver
        self.w_vertices: np.ndarray | None = None
        self._saved: np.ndarray | None = None

    def prepare(self, dt: float) -> float:
        if self.w_vertices is None:
            self.w_vertices = vertex_values(self.velocity_solver.compute())
        return dt

    def move(self, dt: float) -> None:
        assert self.w_vertices is not None
        self._saved = self.mesh.ngmesh.Coordinates().copy()
        move_mesh(self.mesh, dt * self.w_vertices)

    def check(self) -> str | None:
        areas = signed_areas(self.mesh)
        if np.any(areas <= 0):
            return f"{int(np.sum(areas <= 0))} inverted triangle(s) after the mesh move"
        return None

    def undo(self) -> None:
        if self._saved is not None:
            self.mesh.ngmesh.Coordinates()[:] = self._saved

    def after_accept(self) -> None:
        self.w_vertices = None
        self._saved = None


MeshVelocitySolver = VerticalMeshVelocity | ElasticMeshVelocity | LagrangeMeshVelocity
