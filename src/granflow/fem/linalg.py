"""Sparse LU with reuse of the symbolic factorisation across reassemblies."""

from __future__ import annotations

import ngsolve as ngs


class ReusableLU:
    """UMFPACK factorisation of ``form.mat`` whose symbolic analysis is kept.

    The momentum system (3.2) is not symmetric (ALE convection), so a general LU is used;
    ``update`` refactorises numerically after ``form.Assemble()`` while the sparsity
    pattern is unchanged, ``reset`` forces a fresh analysis (after remeshing or
    relabelling that reallocates the matrix).
    """

    def __init__(self, form: ngs.BilinearForm, freedofs: ngs.BitArray) -> None:
        self._form = form
        self._freedofs = freedofs
        self._inverse = None
        self.factorisations = 0

    def reset(self) -> None:
        self._inverse = None

    def update(self) -> None:
        """Refactorise after the form was reassembled."""
        if self._inverse is None:
            self._inverse = self._form.mat.Inverse(self._freedofs, inverse="umfpack")
        else:
            self._inverse.Update()
        self.factorisations += 1

    def solve(self, rhs: ngs.BaseVector, out: ngs.BaseVector) -> None:
        out.data = self._inverse * rhs
