"""Sparse LU with reuse of the symbolic factorisation across reassemblies.

The direct solver is PARDISO when Intel MKL is installed (a default dependency on x86-64,
where Intel ships it), else UMFPACK (NGSolve's own). PARDISO's numeric refactorisation of the
collapse systems is several times faster (docs/performance.md, the solver choice, from
benchmarks/linear_algebra.py); both give the same solution to round-off.
"""

from __future__ import annotations

from functools import cache

import ngsolve as ngs
from pyngcore import Flags

SOLVERS = ("auto", "umfpack", "pardiso", "fieldsplit")   # fieldsplit: fem/fieldsplit.py
# NGSolve's direct solver of a matrix distributed over MPI ranks: gathered on rank 0 and
# factorised there (benchmarks/three_d_solvers.py). It has no numeric refactorisation:
# each update factorises afresh.
MASTER_INVERSE = "masterinverse"
# No iterative refinement of each PARDISO solve (NGSolve's configuration allows it): on the
# column systems it took most of a solve's time and left the residual at round-off either
# way. MKL still refines when the factorisation perturbed a pivot (iparm[7] = 0, MKL manual).
PARDISO_FLAGS = {"refinement": 0}
# From this many unknowns on, the nested-dissection ordering of METIS instead of minimum
# degree: it factorises the large systems faster (docs/performance.md, the scaling table,
# from benchmarks/scaling.py); below, the default trapezoid gains nothing, and the order of
# the pivots, hence the round-off, of the verified small runs stays as it was.
METIS_FROM_UNKNOWNS = 20_000


@cache
def pardiso_available() -> bool:
    """Whether NGSolve can load PARDISO (from the MKL wheel)."""
    mesh = ngs.Mesh(ngs.unit_square.GenerateMesh(maxh=0.25))
    space = ngs.H1(mesh, order=1)
    u, v = space.TnT()
    a = ngs.BilinearForm(space)
    a += u * v * ngs.dx
    a.Assemble()
    try:
        a.mat.Inverse(space.FreeDofs(), inverse="pardiso")
    except Exception:  # NGSolve raises a plain exception when MKL cannot be loaded
        return False
    return True


def distributed(mesh: ngs.Mesh) -> bool:
    """Whether ``mesh`` is one part of a mesh distributed over several MPI ranks."""
    return mesh.comm.size > 1


def direct_solver(choice: str = "auto") -> str:
    """The NGSolve inverse type for ``numerics.linear_solver``."""
    if choice == "auto":
        return "pardiso" if pardiso_available() else "umfpack"
    if choice == "pardiso" and not pardiso_available():
        raise RuntimeError("numerics.linear_solver = 'pardiso' needs Intel MKL: "
                           "pip install mkl (x86-64 only), or use 'umfpack'")
    return choice


def solver_in_use(choice: str = "auto") -> str:
    """``direct_solver`` for reports (summary.json): never raises, says "unavailable"."""
    try:
        return direct_solver(choice)
    except RuntimeError:
        return f"{choice} (unavailable)"


class ReusableLU:
    """Sparse LU (UMFPACK or PARDISO) factorisation of ``form.mat`` whose symbolic analysis is kept.

    The momentum system (3.2) is not symmetric (ALE convection), so a general LU is used;
    ``update`` refactorises numerically after ``form.Assemble()`` while the sparsity
    pattern is unchanged, ``reset`` forces a fresh analysis (after remeshing or
    relabelling that reallocates the matrix).
    """

    def __init__(self, form: ngs.BilinearForm, freedofs: ngs.BitArray,
                 solver: str = "umfpack") -> None:
        self._form = form
        self._solver = solver
        self._freedofs = freedofs
        self._inverse = None
        self.factorisations = 0

    def reset(self) -> None:
        self._inverse = None

    def set_free_dofs(self, freedofs: ngs.BitArray) -> None:
        """Factorise for these degrees of freedom from the next update on."""
        self._freedofs = freedofs
        self.reset()

    def update(self) -> None:
        """Refactorise after the form was reassembled."""
        if self._inverse is None or self._solver == MASTER_INVERSE:
            flags = None
            if self._solver == "pardiso":
                large = self._freedofs.NumSet() >= METIS_FROM_UNKNOWNS
                flags = Flags(PARDISO_FLAGS | ({"ordering": "metis"} if large else {}))
            self._inverse = self._form.mat.Inverse(self._freedofs, inverse=self._solver,
                                                   flags=flags)
        else:
            self._inverse.Update()
        self.factorisations += 1

    def solve(self, rhs: ngs.BaseVector, out: ngs.BaseVector) -> None:
        out.data = self._inverse * rhs

    def work(self) -> dict[str, int]:
        """An iterative solve's counts for summary.json; a direct solve has none."""
        return {}
