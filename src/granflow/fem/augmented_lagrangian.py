"""The augmented Lagrangian method (ALG2) for the unregularised Drucker-Prager law.

Ionescu, Mangeney, Bouchut and Roche (2015, J. Non-Newtonian Fluid Mech. 219, 1-18) solve
the viscoplastic step without the eps of (2.13): the plastic part of the dissipation,
kappa |Du| with kappa = sqrt(2) mu_s [p]_+ (2.4), is split off on an auxiliary strain rate
d = Du with a multiplier lambda, and the augmented Lagrangian

    ... + int eta |Du|^2 + kappa |d| + lambda : (Du - d) + r/2 |Du - d|^2

is minimised by alternating (Uzawa / ALG2, Glowinski and Le Tallec 1989):

1. (u, p): the linear step of (3.2) with the stress 2 eta Du + r (Du - d) + lambda, i.e.
   (2 eta + r) (Du, Dv) on the left and (r d - lambda, Dv) on the right; convection and the
   wall friction are frozen at the current iterate as in Picard's (3.2);
2. d = max(0, 1 - kappa / (r |tau|)) tau with tau = Du + lambda / r: the projection that
   makes the rigid zones exact (d = 0 where |tau| <= kappa / r), kappa from the new p;
3. lambda <- lambda + r (Du - d).

At convergence lambda is the plastic stress: |lambda| <= kappa, lambda = kappa Du / |Du|
where Du != 0. d and lambda are symmetric tensors, discontinuous P1 per triangle (Du of a
P2 velocity is such a field); the projection of step 2 is applied pointwise and projected
back onto that space. ``r`` (Pa s) is the augmentation parameter ``numerics.al_r``.
Convergence: the velocity change of an iteration below ``tol`` relative to the velocity,
the test of (3.2). (Also requiring ||Du - d|| <= tol ||Du|| made steps of the plug flow at
dZ = 0.125 fail after 1000 iterations with the velocity converged to 1e-14: the
constraint converges much more slowly than the velocity; its effect on accuracy is what
the error against the 1D reference measures.)
"""

from __future__ import annotations

import math

import ngsolve as ngs

from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.forms import Symbols, strain_rate
from granflow.fem.nonlinear import IterationReport, NonlinearSolver
from granflow.physics import DruckerPrager


class AugmentedStress:
    """(2 eta + r) Du : Dv on the left, (r d - lambda) : Dv on the right: the stress of
    step 1; it replaces ``ViscoplasticStress`` in the momentum terms."""

    def __init__(self, rheology: DruckerPrager, augmentation: float,
                 strain: ngs.GridFunction, multiplier: ngs.GridFunction) -> None:
        self.rheology, self.r = rheology, augmentation
        self.strain, self.multiplier = strain, multiplier

    def wall_deviatoric(self, u_lin: ngs.CoefficientFunction, p_lin: ngs.CoefficientFunction,
                        frozen: bool) -> ngs.CoefficientFunction:
        """sigma' at the iterate, 2 eta Du + lambda, traced on a wall (friction load)."""
        sigma = 2.0 * self.rheology.viscosity * strain_rate(u_lin) + self.multiplier
        return ngs.BoundaryFromVolumeCF(sigma) if frozen else sigma

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        coefficient = 2.0 * self.rheology.viscosity + self.r
        return coefficient * ngs.InnerProduct(strain_rate(s.u), strain_rate(s.v)) * ngs.dx

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        source = self.r * self.strain - self.multiplier
        return ngs.InnerProduct(source, strain_rate(s.v)) * ngs.dx


def tensor_space(mesh: ngs.Mesh) -> ngs.FESpace:
    """Symmetric 2x2 tensors, discontinuous P1 on each triangle."""
    return ngs.MatrixValued(ngs.L2(mesh, order=1), symmetric=True)


class AugmentedLagrangian:
    """The ALG2 iteration of one implicit-Euler step on ``state`` (u, p)."""

    def __init__(self, rheology: DruckerPrager, augmentation: float,
                 nonlinear: NonlinearSolver, strain: ngs.GridFunction,
                 multiplier: ngs.GridFunction) -> None:
        self.rheology, self.r = rheology, augmentation
        self.nonlinear, self.system = nonlinear, nonlinear.picard_system
        self.state = nonlinear.state
        self.strain, self.multiplier = strain, multiplier
        self._next = ngs.GridFunction(strain.space)
        vec = self.state.vec
        self._trial, self._delta = vec.CreateVector(), vec.CreateVector()

    def solve(self, tol: float, max_iterations: int, velocity_floor: float = 0.0
              ) -> IterationReport:
        mesh = self.state.space.mesh
        self.nonlinear.prepare_norm()
        l2 = self.nonlinear.velocity_l2
        floor = velocity_floor * math.sqrt(ngs.Integrate(ngs.CF(1.0), mesh))
        x = self.state.vec
        u, p = self.state.components
        # steps 2 and 3 as coefficient functions of the live fields, built once per solve:
        # the projection onto the yield set (kappa of the new pressure), then the multiplier
        du = strain_rate(u)
        kappa = self.rheology.yield_stress(p, NGSOLVE_OPS)
        tau = du + (1.0 / self.r) * self.multiplier
        norm_tau = ngs.sqrt(ngs.InnerProduct(tau, tau) + 1e-300)
        projection = ngs.IfPos(norm_tau - kappa / self.r,
                               (1.0 - kappa / (self.r * norm_tau)) * tau, 0 * tau)
        update = self.multiplier + self.r * (du - self.strain)
        change = math.inf
        for k in range(1, max_iterations + 1):
            norm_old = max(l2(x), floor)
            self.system.prepare()               # the right-hand side reads d and lambda
            self.system.iterate(self._trial)
            self._delta.data = self._trial - x
            x.data = self._trial
            self._next.Set(projection)
            self.strain.vec.data = self._next.vec
            self._next.Set(update)
            self.multiplier.vec.data = self._next.vec
            change = l2(self._delta) / norm_old if norm_old > 0 else 0.0
            if not (math.isfinite(change) and math.isfinite(self.multiplier.vec.Norm())):
                return IterationReport(False, k, math.nan, finite=False, picard_iterations=k)
            if change < tol:
                return IterationReport(True, k, change, picard_iterations=k)
        return IterationReport(False, max_iterations, change, picard_iterations=max_iterations)
