"""Two parts of the fieldsplit solve (``fem/fieldsplit.py``) that PETSc does not provide
as options: the system's symmetric diagonal scaling, and the Cahouet-Chabard
preconditioner of the Schur complement.

The scaling: the velocity rows and columns by diag(A00)^-1/2, the pressure ones by
diag(A10 diag(A00)^-1 A01)^-1/2 (the diagonal of ``selfp``'s Schur complement). In the
regularised law the rigid cells' viscosity is 1 / eps times the flowing ones', so
unscaled the residual's Euclidean norm is the rigid rows' alone: FGMRes could meet its
tolerance there while the flowing rows are still far from the solution.

Cahouet and Chabard: the Schur complement -B A^-1 B^T of a system whose velocity block is
rho / dt M + (viscous), approximated through its inverse as the sum of the inverse of the
pressure mass weighted by 2 / m (the viscous share; by its diagonal) and the inverse of
the pressure Laplacian times dt / rho (the inertia's share; one GAMG cycle), p = 0 on the
free surface by a Robin term (``common/block_preconditioner.py`` in benchmarks/ builds
the same forms for NGSolve's own solvers).
"""

from __future__ import annotations

from typing import Any

import ngsolve as ngs

from granflow.fem.measure import Coordinates
from granflow.geometry.labels import SURFACE


def scaling(matrix: Any, velocity: Any, pressure: Any) -> Any:
    """The vector d of the symmetric scaling diag(d) A diag(d) (module docstring)."""
    diagonal = matrix.getDiagonal()
    d = diagonal.duplicate()
    whole = diagonal.copy()
    whole.sqrtabs()
    whole.reciprocal()
    part = whole.getSubVector(velocity)
    coupling = matrix.createSubMatrix(pressure, velocity)
    coupling.diagonalScale(R=part)                 # A10 diag(A00)^-1/2
    whole.restoreSubVector(velocity, part)
    schur = coupling.matTransposeMult(coupling).getDiagonal()
    schur.sqrtabs()
    schur.reciprocal()
    d.set(0.0)
    for index_set, values in ((velocity, None), (pressure, schur)):
        target = d.getSubVector(index_set)
        if values is None:
            source = whole.getSubVector(index_set)
            source.copy(target)
            whole.restoreSubVector(index_set, source)
        else:
            values.copy(target)
        d.restoreSubVector(index_set, target)
    return d


def schur_forms(space: ngs.FESpace, viscosity: ngs.CoefficientFunction, dt_over_rho: float,
                coords: Coordinates) -> tuple[ngs.BilinearForm, ngs.BilinearForm]:
    """The pressure mass weighted by 2 / m and the pressure Laplacian times dt / rho (with
    the free surface's Robin term), on the Taylor-Hood ``space`` (its pressure rows only),
    so that they map to PETSc as the system does."""
    (_, p), (_, q) = space.TnT()
    mass = ngs.BilinearForm(space)
    mass += coords.dx(2.0 / viscosity * p * q)
    laplace = ngs.BilinearForm(space)
    laplace += coords.dx(dt_over_rho * ngs.grad(p) * ngs.grad(q))
    laplace += dt_over_rho / ngs.specialcf.mesh_size * p * q * ngs.ds(SURFACE)
    return mass, laplace


class CahouetChabard:
    """petsc4py's python preconditioner context of the Schur block: y = -(diag(Mw)^-1 +
    GAMG(L)) x in the unscaled pressure, with ``d`` the scaling's pressure part (or None):
    in the scaled system y = -d^-1 (...)(d^-1 x)."""

    def __init__(self) -> None:
        self._inverse_mass: Any = None
        self._laplace: Any = None
        self._d: Any = None
        self._work: Any = None

    def update(self, mass: Any, laplace: Any, d: Any | None) -> None:
        """Take the reassembled pressure mass and Laplacian (PETSc matrices on the
        pressure rows) and the scaling's pressure part."""
        from petsc4py import PETSc

        self._inverse_mass = mass.getDiagonal()
        self._inverse_mass.reciprocal()
        if self._laplace is None:
            self._laplace = PETSc.PC().create(comm=laplace.getComm())
            self._laplace.setType("gamg")
        self._laplace.setOperators(laplace)
        self._laplace.setUp()
        self._d = d
        self._work = None

    def apply(self, pc: Any, x: Any, y: Any) -> None:
        if self._work is None:
            self._work = (x.duplicate(), x.duplicate())
        source, part = self._work
        x.copy(source)
        if self._d is not None:
            source.pointwiseDivide(source, self._d)
        self._laplace.apply(source, y)
        part.pointwiseMult(self._inverse_mass, source)
        y.axpy(1.0, part)
        if self._d is not None:
            y.pointwiseDivide(y, self._d)
        y.scale(-1.0)
