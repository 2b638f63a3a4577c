"""The fixed-point (Picard) iteration (3.2) and its report."""

from __future__ import annotations

import math
from dataclasses import dataclass

import ngsolve as ngs

from granflow.fem.linalg import ReusableLU


@dataclass(frozen=True)
class IterationReport:
    """Outcome of one nonlinear solve: converged or not, how many linear solves, last change."""

    converged: bool
    iterations: int
    relative_change: float
    finite: bool = True


class PicardIteration:
    """Iterate (3.2) until ||u^{k+1} - u^k||_L2 / ||u^k||_L2 < tol (paper section 3.1).

    ``iterate`` holds (u^k, p^k) and is overwritten with each new iterate; the forms
    read it, so each pass only reassembles ``a`` and refactorises numerically.
    """

    def __init__(self, a: ngs.BilinearForm, f: ngs.LinearForm, iterate: ngs.GridFunction,
                 freedofs: ngs.BitArray) -> None:
        self.a, self.f, self.iterate = a, f, iterate
        space = iterate.space
        (u, _), (v, _) = space.TnT()
        self._mass = ngs.BilinearForm(space)
        self._mass += u * v * ngs.dx
        self._lu = ReusableLU(a, freedofs)
        self._new = iterate.vec.CreateVector()
        self._diff = iterate.vec.CreateVector()
        self._work = iterate.vec.CreateVector()

    def reset_factorisation(self) -> None:
        """Forget the symbolic LU (the sparsity pattern changed)."""
        self._lu.reset()

    def _l2(self, vec: ngs.BaseVector) -> float:
        self._work.data = self._mass.mat * vec
        return math.sqrt(max(ngs.InnerProduct(vec, self._work), 0.0))

    def solve(self, tol: float, max_iterations: int,
              velocity_floor: float = 0.0) -> IterationReport:
        """Run the iteration from the current ``iterate``; the mesh must already be moved.

        The change is measured relative to max(||u^k||, velocity_floor |Omega|^1/2): with a
        zero floor this is the paper's criterion; a floor (m/s) stops the iteration from
        chasing relative changes of a mass that is at rest, where ||u^k|| -> 0.
        """
        self.f.Assemble()
        self._mass.Assemble()
        floor = velocity_floor * math.sqrt(ngs.Integrate(ngs.CF(1.0), self.iterate.space.mesh)) \
            if velocity_floor > 0 else 0.0
        change = math.inf
        for k in range(1, max_iterations + 1):
            self.a.Assemble()
            self._lu.update()
            self._lu.solve(self.f.vec, self._new)
            self._diff.data = self._new - self.iterate.vec
            norm_old = max(self._l2(self.iterate.vec), floor)
            norm_diff = self._l2(self._diff)
            self.iterate.vec.data = self._new
            if not math.isfinite(norm_diff):
                return IterationReport(False, k, math.nan, finite=False)
            change = norm_diff / norm_old if norm_old > 0 else (0.0 if norm_diff == 0 else math.inf)
            if change < tol:
                return IterationReport(True, k, change)
        return IterationReport(False, max_iterations, change)
