"""Nonlinear solves of one implicit-Euler step: the paper's fixed-point iteration (3.2) and
a damped Newton method on the same residual, with a fall-back to Picard iterations.

Both are built from the same terms (``fem/forms.py``): Picard from their matrix and
right-hand side frozen at the iterate, Newton from the residual whose coefficients are the
unknowns, linearised symbolically. Convergence is measured on the velocity in L2, relative to
max(||u||, floor |Omega|^1/2).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import ngsolve as ngs
import numpy as np

from granflow.fem.anderson import Anderson
from granflow.fem.fieldsplit import FIELDSPLIT, FieldsplitSolve, combined_work
from granflow.fem.linalg import ReusableLU
from granflow.simulation.outcomes import IterationReport

if TYPE_CHECKING:
    from granflow.fem.primal_dual import DualVariable

NEWTON_MIN_DAMPING = 1.0 / 64   # below this damping factor Newton has stalled
PICARD_FALLBACK_ITERATIONS = 4  # fixed-point iterations run when Newton stalls


def linear_solve(form: ngs.BilinearForm, freedofs: ngs.BitArray,
                 solver: str) -> ReusableLU | FieldsplitSolve:
    """The solve of ``form``'s matrix that ``numerics.linear_solver`` names: a sparse LU,
    or PETSc's fieldsplit GMRes (``fem/fieldsplit.py``)."""
    if solver == FIELDSPLIT:
        return FieldsplitSolve(form, freedofs)
    return ReusableLU(form, freedofs, solver)


class FixedPointSystem:
    """The matrix A(x^k) = A_k + A_0 and right-hand side f of (3.2), with a reusable LU.

    A_0 (``constant``: inertia, incompressibility, penalty) is assembled once per step and
    added to A_k, the part whose coefficients read the iterate, at each iteration (both
    forms share the sparsity pattern of the space).
    """

    def __init__(self, a: ngs.BilinearForm, f: ngs.LinearForm, freedofs: ngs.BitArray,
                 solver: str = "umfpack", constant: ngs.BilinearForm | None = None,
                 correction: tuple[ngs.BilinearForm, ngs.LinearForm] | None = None,
                 rhs_reads_iterate: bool = False) -> None:
        self.a, self.f, self.constant, self.correction = a, f, constant, correction
        self.rhs_reads_iterate = rhs_reads_iterate    # f is assembled at every iteration
        self.lu = linear_solve(a, freedofs, solver)
        self._rhs = f.vec.CreateVector()

    def prepare(self) -> None:
        """Assemble what stays fixed during one step's iterations."""
        self.f.Assemble()
        if self.constant is not None:
            self.constant.Assemble()

    def assemble_rhs(self) -> None:
        """Reassemble f alone (ALG2 changes it at every iteration, A_0 stays)."""
        self.f.Assemble()

    def assemble(self, corrected: bool = False) -> ngs.BaseMatrix:
        """A(x^k) = A_k + A_0 into ``a.mat`` (A_0 as ``prepare`` left it), plus the
        primal-dual correction if ``corrected``."""
        self.a.Assemble()
        parts = [] if self.constant is None else [self.constant]
        if corrected and self.correction is not None:
            self.correction[0].Assemble()
            parts.append(self.correction[0])
        total = self.a.mat.AsVector()
        for form in parts:
            part = form.mat.AsVector()
            if len(total) != len(part):
                raise RuntimeError("the parts of the matrix of (3.2) have different "
                                   "sparsity patterns")
            total.data += part
        return self.a.mat

    def iterate(self, out: ngs.BaseVector, corrected: bool = False) -> None:
        """x^{k+1} = A(x^k)^-1 f; A reads x^k from the iterate it was built on. With
        ``corrected``, the primal-dual correction's matrix and right-hand side join."""
        self.assemble(corrected)
        self.lu.update()
        if self.rhs_reads_iterate:
            self.f.Assemble()
        if not (corrected and self.correction is not None):
            self.lu.solve(self.f.vec, out)
            return
        self.correction[1].Assemble()
        self._rhs.data = self.f.vec + self.correction[1].vec
        self.lu.solve(self._rhs, out)

    def reset(self) -> None:
        self.lu.reset()


class ResidualSystem:
    """A residual form R(x), its linearisation at x and the LU of that linearisation."""

    def __init__(self, form: ngs.BilinearForm, freedofs: ngs.BitArray,
                 solver: str = "umfpack") -> None:
        self.form = form
        self.lu = linear_solve(form, freedofs, solver)

    def linearise(self, x: ngs.BaseVector) -> None:
        self.form.AssembleLinearization(x)
        self.lu.update()

    def residual(self, x: ngs.BaseVector, out: ngs.BaseVector) -> None:
        self.form.Apply(x, out)

    def solve(self, rhs: ngs.BaseVector, out: ngs.BaseVector) -> None:
        self.lu.solve(rhs, out)

    def reset(self) -> None:
        self.lu.reset()


PRIMAL_DUAL_AFTER = 2    # fixed-point iterations before the dual correction may switch on
PRIMAL_DUAL_ROUND = 8    # corrected iterations judged together (undone if no gain)
HYBRID_PICARD_ITERATIONS = 3  # fixed-point iterations before the hybrid judges their pace
HYBRID_PATIENCE = 4           # more predicted fixed-point iterations than this: Newton


def _slow(change: float, previous: float, tol: float) -> bool:
    """Whether the fixed-point iteration, contracting at change/previous, needs more than
    HYBRID_PATIENCE further iterations to reach tol."""
    rate = change / previous if previous > 0 and math.isfinite(previous) else 1.0
    if rate >= 1.0:
        return True
    return math.log(tol / change) / math.log(rate) > HYBRID_PATIENCE


class _Counter:
    def __init__(self) -> None:
        self.newton = self.picard = self.solves = self.fallbacks = 0

    def report(self, converged: bool, change: float, finite: bool = True) -> IterationReport:
        return IterationReport(converged, self.newton + self.picard, change, finite,
                               self.solves, self.newton, self.picard, self.fallbacks)


class NonlinearSolver:
    """Picard (3.2) and damped Newton on ``state`` (the iterate, overwritten in place)."""

    def __init__(self, picard: FixedPointSystem, newton: ResidualSystem,
                 state: ngs.GridFunction, dual: DualVariable | None = None,
                 anderson_depth: int = 0) -> None:
        self.picard_system, self.newton_system, self.state = picard, newton, state
        self.dual = dual
        self._saved = state.vec.CreateVector()
        space = state.space
        (u, _), (v, _) = space.TnT()
        self._mass = ngs.BilinearForm(space)
        self._mass += u * v * ngs.dx
        self.scratch = ngs.GridFunction(space)   # for callers' temporary fields
        self.carried_work: dict[str, int] = {}   # ``linear_work`` on the meshes before
        vec = state.vec
        self._r, self._delta, self._bar = vec.CreateVector(), vec.CreateVector(), vec.CreateVector()
        self._trial, self._work = vec.CreateVector(), vec.CreateVector()
        self.anderson = Anderson(anderson_depth, self._weighted) if anderson_depth else None
        # a field solved with each iterate (a nonlocal law's fluidity, fem/fluidity.py):
        # returns its relative change, which joins the convergence test
        self.coupled: Callable[[], float] | None = None

    def _weighted(self, values: np.ndarray) -> np.ndarray:
        """M v for the velocity L2 inner product of ``velocity_l2`` (numpy in and out)."""
        self._bar.FV().NumPy()[:] = values
        self._work.data = self._mass.mat * self._bar
        return self._work.FV().NumPy().copy()

    def linear_work(self) -> dict[str, int]:
        """The iterative solves' counts (``fieldsplit.KRYLOV_KEYS``) over the run: this
        solver's and those carried from the solvers of the meshes before; empty with a
        direct solve."""
        return combined_work(self.carried_work, self.picard_system.lu.work(),
                             self.newton_system.lu.work())

    def reset_factorisations(self) -> None:
        """Forget the symbolic LUs (the sparsity pattern changed)."""
        self.picard_system.reset()
        self.newton_system.reset()

    def set_free_dofs(self, freedofs: ngs.BitArray) -> None:
        """Solve for these degrees of freedom from now on (the walls' held components
        changed: ``fem/held_walls.py``)."""
        for system in (self.picard_system, self.newton_system):
            system.lu.set_free_dofs(freedofs)

    def velocity_l2(self, vec: ngs.BaseVector) -> float:
        """L2 norm of the velocity part of ``vec`` on the mesh of the last solve."""
        return self._l2(vec)

    def prepare_norm(self) -> None:
        """Assemble the velocity mass matrix of ``velocity_l2`` on the current mesh."""
        self._mass.Assemble()

    def _l2(self, vec: ngs.BaseVector) -> float:
        """L2 norm of the velocity part of ``vec``."""
        self._work.data = self._mass.mat * vec
        return math.sqrt(max(ngs.InnerProduct(vec, self._work), 0.0))

    def _reference(self, velocity_floor: float) -> float:
        if velocity_floor <= 0:
            return 0.0
        return velocity_floor * math.sqrt(ngs.Integrate(ngs.CF(1.0), self.state.space.mesh))

    @staticmethod
    def _relative(change: float, norm: float) -> float:
        if not math.isfinite(change):
            return math.nan
        return change / norm if norm > 0 else (0.0 if change == 0 else math.inf)

    # --- Picard (3.2) ----------------------------------------------------------------
    def solve_picard(self, tol: float, max_iterations: int,
                     velocity_floor: float = 0.0) -> IterationReport:
        """Iterate (3.2) until ||u^{k+1} - u^k|| / max(||u^k||, floor) < tol (section 3.1)."""
        self._mass.Assemble()
        self.picard_system.prepare()
        count = _Counter()
        if self.dual is not None:
            self.dual.prepare()
        change = self._picard(tol, max_iterations, self._reference(velocity_floor), count)
        return count.report(change < tol, change, not math.isnan(change))

    def _picard(self, tol: float, iterations: int, floor: float, count: _Counter,
                give_up_after: int = 0) -> float:
        """Up to ``iterations`` fixed-point iterations; the last relative change.

        With ``give_up_after`` > 0, stop early once that many iterations are done and the
        observed contraction predicts more than HYBRID_PATIENCE further ones.

        With a dual variable (``primal-dual``): from iteration PRIMAL_DUAL_AFTER on, when
        the plain iteration contracts slowly, one plain iteration seeds lambda and the
        corrected iterations of ``fem/primal_dual.py`` follow, in rounds of
        PRIMAL_DUAL_ROUND. A round that ends with a larger change than it started from is
        undone (the iterate it started from is restored) and the step goes on with plain
        iterations (rounds whose change first grew 4 to 44 times still end below it: 39 of
        the 112 rounds of the default collapse). A corrected iterate that meets tol is
        followed by a plain one, which decides convergence: an accepted state passes the
        fixed-point test of section 3.1 exactly as Picard's do.
        """
        x, system, dual = self.state.vec, self.picard_system, self.dual
        change = previous = math.inf
        mode, banned, used, start_change = "plain", False, 0, math.inf
        anderson = self.anderson
        if anderson is not None:
            anderson.reset()
        for k in range(1, iterations + 1):
            norm_old = max(self._l2(x), floor)
            corrected = mode == "corrected"
            if mode == "seeding":
                dual.start()
            system.iterate(self._trial, corrected)
            count.picard += 1
            count.solves += 1
            if mode != "plain":
                dual.update(self._trial)
            self._delta.data = self._trial - x
            before = x.FV().NumPy().copy() if anderson is not None and mode == "plain" else None
            x.data = self._trial
            previous, change = change, self._relative(self._l2(self._delta), norm_old)
            if self.coupled is not None:
                change = max(change, self.coupled())
            if mode == "seeding":               # a plain iterate: the round starts here
                mode, used, start_change = "corrected", 0, change
                self._saved.data = x
            elif corrected:
                used += 1
                if change < tol:                # confirm with a plain iteration of (3.2)
                    mode = "plain"
                    continue
                if used >= PRIMAL_DUAL_ROUND:
                    if not change < start_change:   # the round did not pay: undo it
                        x.data = self._saved
                        change, mode, banned = start_change, "plain", True
                        continue
                    self._saved.data = x
                    used, start_change = 0, change
            if math.isnan(change) or change < tol:
                break
            if give_up_after and k >= give_up_after and _slow(change, previous, tol):
                break
            if (dual is not None and mode == "plain" and not banned
                    and k >= PRIMAL_DUAL_AFTER and _slow(change, previous, tol)):
                mode = "seeding"
            if anderson is not None:
                if mode == "plain" and before is not None:   # mix the next plain iterate
                    x.FV().NumPy()[:] = anderson.mix(before, x.FV().NumPy())
                else:
                    anderson.reset()
        return change

    # --- hybrid ---------------------------------------------------------------------------
    def solve_hybrid(self, tol: float, max_iterations: int,
                     velocity_floor: float = 0.0) -> IterationReport:
        """Fixed-point iterations (3.2) while they contract fast, then Newton.

        Near a good initial guess (small steps, slow flow) Picard converges in two or three
        cheap iterations; where it contracts slowly (small eps, plug flow) or cycles (the
        pressure-dependent friction at a thin front), Newton takes over from its iterate.
        """
        self._mass.Assemble()
        self.picard_system.prepare()
        floor = self._reference(velocity_floor)
        count = _Counter()
        change = self._picard(tol, min(max_iterations, 4 * HYBRID_PICARD_ITERATIONS), floor,
                              count, give_up_after=HYBRID_PICARD_ITERATIONS)
        if math.isnan(change):
            return count.report(False, math.nan, finite=False)
        if change < tol:
            return count.report(True, change)
        return self._newton(tol, max_iterations, floor, count)

    # --- Newton --------------------------------------------------------------------------
    def solve_newton(self, tol: float, max_iterations: int,
                     velocity_floor: float = 0.0) -> IterationReport:
        """Damped Newton with Deuflhard's natural monotonicity test.

        Each iteration factorises the consistent tangent at x, takes the Newton correction
        delta and the largest damping lambda in {1, 1/2, ...} whose simplified correction
        J(x)^-1 R(x - lambda delta) is smaller than (1 - lambda/4) ||delta|| (an
        affine-invariant test, blind to the 1e12 penalty scaling of the residual).
        Converged when that simplified correction, which estimates the remaining error, is
        below tol relative to max(||u||, floor) after a full step. A damping below
        NEWTON_MIN_DAMPING counts as a stall: a few Picard iterations follow, then Newton
        resumes.
        """
        self._mass.Assemble()
        return self._newton(tol, max_iterations, self._reference(velocity_floor), _Counter())

    def _newton(self, tol: float, max_iterations: int, floor: float,
                count: _Counter) -> IterationReport:
        x, system = self.state.vec, self.newton_system
        change = math.inf
        while count.newton + count.picard < max_iterations:
            system.linearise(x)
            system.residual(x, self._r)
            system.solve(self._r, self._delta)
            count.newton += 1
            count.solves += 1
            norm_delta = self._l2(self._delta)
            if not math.isfinite(norm_delta):
                return count.report(False, math.nan, finite=False)
            damping = 1.0
            while True:
                self._trial.data = x - damping * self._delta
                system.residual(self._trial, self._r)
                system.solve(self._r, self._bar)
                count.solves += 1
                norm_bar = self._l2(self._bar)
                if math.isfinite(norm_bar) and norm_bar <= (1.0 - damping / 4) * norm_delta:
                    break
                damping *= 0.5
                if damping < NEWTON_MIN_DAMPING:
                    break
            if damping < NEWTON_MIN_DAMPING:       # stalled: fixed-point iterations, then on
                count.fallbacks += 1
                self.picard_system.prepare()
                left = max_iterations - count.newton - count.picard
                change = self._picard(tol, min(PICARD_FALLBACK_ITERATIONS, left), floor, count)
                if math.isnan(change):
                    return count.report(False, math.nan, finite=False)
                if change < tol:
                    return count.report(True, change)
                continue
            x.data = self._trial
            norm = max(self._l2(x), floor)
            change = self._relative(norm_bar, norm)
            if self.coupled is not None:
                change = max(change, self.coupled())

            if damping == 1.0 and change < tol:
                x.data -= self._bar                 # the simplified Newton step, for free
                return count.report(True, change)
        return count.report(False, change)
