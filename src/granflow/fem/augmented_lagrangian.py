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
   makes the rigid zones exact (d = 0 where |tau| <= kappa / r);
3. lambda <- lambda + r (Du - d).

At convergence lambda is the plastic stress: |lambda| <= kappa, lambda = kappa Du / |Du|
where Du != 0. d and lambda are symmetric tensors, discontinuous P1 per triangle (Du of a
P2 velocity is such a field); the projection of step 2 is applied pointwise and projected
back onto that space. ``r`` (Pa s) starts at ``numerics.al_r``.

The pressure in kappa = sqrt(2) mu_s [p*]_+ (2.4) is frozen during the iteration and
refreshed (p* <- p) each time the iteration has converged to an inner tolerance
max(tol, 0.1 x the last refresh's relative change of p): an inexact outer fixed point on
p, as Picard's (3.2) lags p. The pressure of an iterate is not the physical one while
Du != d (it balances r (Du - d) as well): taking kappa from the latest p at every
iteration (or from the previous iteration's) made the first step of a column oscillate
for ever (velocity changes of 1e-4 to 1e-1 per iteration with r = 1e4 Pa s); with kappa
frozen the same step converges. On the first step of a rectangle the refreshes moved p by
35 %, 19 %, 8 %, 5 %, ... (the release makes it non-hydrostatic).

r is balanced during the iteration (Boyd et al. 2011, Found. Trends Mach. Learn. 3,
section 3.4.1): the relative primal residual ||Du - d|| / ||Du|| and dual residual
r ||d - d_prev|| / ||lambda|| are kept within a factor 10 of each other by doubling or
halving r. A fixed r is either slow to build the plastic stress of a column starting from
rest (r = 20 Pa s: ||lambda|| grows by ~r Du per iteration, 500 iterations were not
enough) or slow to let the velocity follow (r = 1e5 Pa s: the velocity changes by 3e-4
per iteration while still 6 times below its converged value, so a test on the velocity
change alone would stop there).

Converged when, at the same iteration, the velocity change is below ``tol`` relative to
max(||u||, floor) (the test of (3.2)), both residuals are below ``CONSTRAINT_TOL`` (relative
to max(||Du||, floor) and to ||lambda||), and the outer fixed point has converged: p moved
from p* by less than ``PRESSURE_TOL``, or the velocity moved by less than ``tol`` since the
last refresh of p*. The pressure, unlike the velocity, is not unique in the rigid zones
of a rigid-plastic body (any lambda with |lambda| <= kappa that balances the load will
do, and its trace trades with p): on the first step of a rectangle the velocity of this
method is within 1 % of the regularised law's at eps = 1e-6 and its pressure 18 % from it
(L2), and late in a collapse the refreshes moved p by 1e-3 to 1e-2 for ever while the
velocity stood still, which is why the velocity decides.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs

from granflow.fem.coupling import Carriers, Coupling, Flow, Iteration, Site
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.forms import StressTerm, Symbols, strain_rate
from granflow.fem.nonlinear import NonlinearSolver
from granflow.physics import DruckerPrager
from granflow.simulation.outcomes import IterationReport
from granflow.state.spec import Share, array, assign, may_lack, number

CONSTRAINT_TOL = 1e-2      # relative primal and dual residuals at convergence
PRESSURE_TOL = 1e-3        # relative change of kappa's pressure p* at convergence (floor)
OUTER_FORCING = 0.1        # inner tolerance while p* is still moving: 0.1 x its last move
BALANCE_RATIO = 10.0       # residual balancing: change r when one residual is 10x the other
R_MIN, R_MAX = 1e-3, 1e9   # Pa s: the range r is balanced within


def tensor_norm(field: ngs.CoefficientFunction, mesh: ngs.Mesh) -> float:
    """L2 norm of a tensor field."""
    return math.sqrt(max(ngs.Integrate(ngs.InnerProduct(field, field), mesh), 0.0))


class AugmentedStress:
    """(2 eta + r) Du : Dv on the left, (r d - lambda) : Dv on the right: the stress of
    step 1; it replaces ``ViscoplasticStress`` in the momentum terms."""

    def __init__(self, rheology: DruckerPrager, augmentation: ngs.Parameter,
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

    def __init__(self, rheology: DruckerPrager, augmentation: ngs.Parameter,
                 nonlinear: NonlinearSolver, strain: ngs.GridFunction,
                 multiplier: ngs.GridFunction) -> None:
        self.rheology, self.r = rheology, augmentation
        self.nonlinear, self.system = nonlinear, nonlinear.picard_system
        self.state = nonlinear.state
        self.strain, self.multiplier = strain, multiplier
        self._next = ngs.GridFunction(strain.space)
        self._strain_before = strain.vec.CreateVector()
        self.yield_pressure = ngs.GridFunction(self.state.components[1].space)   # p*
        vec = self.state.vec
        self._trial, self._delta = vec.CreateVector(), vec.CreateVector()
        self._outer = vec.CreateVector()       # the iterate at the last refresh of p*
        self._saved = (strain.vec.CreateVector(), multiplier.vec.CreateVector())
        self._saved_r = augmentation.Get()

    def remember(self) -> None:
        """Keep d, lambda and r of the step's start (``restore`` after a rejection)."""
        self._saved[0].data = self.strain.vec
        self._saved[1].data = self.multiplier.vec
        self._saved_r = self.r.Get()

    def restore(self) -> None:
        self.strain.vec.data = self._saved[0]
        self.multiplier.vec.data = self._saved[1]
        self.r.Set(self._saved_r)

    def solve(self, tol: float, max_iterations: int, velocity_floor: float = 0.0
              ) -> IterationReport:
        mesh = self.state.space.mesh
        self.nonlinear.prepare_norm()
        l2 = self.nonlinear.velocity_l2
        root_area = math.sqrt(ngs.Integrate(ngs.CF(1.0), mesh))
        floor = velocity_floor * root_area
        x = self.state.vec
        u, p = self.state.components
        p_star = self.yield_pressure
        p_star.vec.data = p.vec
        # steps 2 and 3 as coefficient functions of the live fields, built once per solve:
        # the projection onto the yield set (kappa of the frozen p*), then the multiplier
        du = strain_rate(u)
        kappa = self.rheology.yield_stress(p_star, NGSOLVE_OPS)
        tau = du + (1.0 / self.r) * self.multiplier
        norm_tau = ngs.sqrt(ngs.InnerProduct(tau, tau) + 1e-300)
        projection = ngs.IfPos(norm_tau - kappa / self.r,
                               (1.0 - kappa / (self.r * norm_tau)) * tau, 0 * tau)
        update = self.multiplier + self.r * (du - self.strain)
        change, moved, refreshed = math.inf, 1.0, False
        for k in range(1, max_iterations + 1):
            norm_old = max(l2(x), floor)
            if k == 1:
                self.system.prepare()
            else:
                self.system.assemble_rhs()      # the right-hand side reads d and lambda
            self.system.iterate(self._trial)
            self._delta.data = self._trial - x
            x.data = self._trial
            self._strain_before.data = self.strain.vec
            self._next.Set(projection)
            self.strain.vec.data = self._next.vec
            self._next.Set(update)
            self.multiplier.vec.data = self._next.vec
            change = l2(self._delta) / norm_old if norm_old > 0 else 0.0
            if not (math.isfinite(change) and math.isfinite(self.multiplier.vec.Norm())):
                return IterationReport(False, k, math.nan, finite=False, picard_iterations=k)
            primal, dual = self._residuals(du, mesh, velocity_floor)
            inner_tol = max(tol, OUTER_FORCING * moved)
            if change < inner_tol and primal < CONSTRAINT_TOL and dual < CONSTRAINT_TOL:
                moved = self._pressure_change(p)
                outer = math.inf
                if refreshed:                   # the velocity's change over the last refresh
                    self._outer.data -= x
                    outer = l2(self._outer) / max(l2(x), floor)
                if change < tol and (moved < PRESSURE_TOL or outer < tol):
                    return IterationReport(True, k, change, picard_iterations=k)
                self._outer.data = x
                refreshed = True
                p_star.vec.data = p.vec         # outer fixed point on kappa's pressure
            self._balance(primal, dual)
        return IterationReport(False, max_iterations, change, picard_iterations=max_iterations)

    def _residuals(self, du: ngs.CoefficientFunction, mesh: ngs.Mesh,
                   velocity_floor: float) -> tuple[float, float]:
        """Relative primal ||Du - d|| / max(||Du||, floor) and dual r ||d - d_prev|| /
        ||lambda|| residuals (the strain floor is the velocity floor over the domain's
        length sqrt|Omega|, in the same L2 norm: ``velocity_floor``)."""
        scale = max(tensor_norm(du, mesh), velocity_floor, 1e-300)
        primal = tensor_norm(du - self.strain, mesh) / scale
        self._strain_before.data -= self.strain.vec
        self._next.vec.data = self._strain_before
        stress = tensor_norm(self.multiplier, mesh)
        dual = self.r.Get() * tensor_norm(self._next, mesh) / stress if stress > 0 else 0.0
        return primal, dual

    def _balance(self, primal: float, dual: float) -> None:
        """Residual balancing: r x 2 when the constraint lags, r / 2 when lambda does."""
        r = self.r.Get()
        if primal > BALANCE_RATIO * dual:
            self.r.Set(min(2.0 * r, R_MAX))
        elif dual > BALANCE_RATIO * primal:
            self.r.Set(max(0.5 * r, R_MIN))

    def _pressure_change(self, p: ngs.GridFunction) -> float:
        """||p - p*|| / ||p*|| (L2): how far the iteration moved kappa's pressure."""
        p_star = self.yield_pressure
        scale = math.sqrt(ngs.Integrate(p_star * p_star, p.space.mesh))
        moved = math.sqrt(ngs.Integrate((p - p_star) * (p - p_star), p.space.mesh))
        return moved / scale if scale > 0 else (0.0 if moved == 0 else math.inf)


@dataclass(frozen=True)
class AugmentedLagrangianSpec:
    """The augmented Lagrangian method in place of the regularised law: r's starting value
    (Pa s), then balanced."""

    augmentation: float

    def build(self, site: Site, fields: Mapping[str, Any]) -> AugmentedLagrangianCoupling:
        if site.coordinates.axisymmetric:
            raise ValueError("the augmented Lagrangian method is plane strain only")
        return AugmentedLagrangianCoupling(site.mesh, self.augmentation)


class AugmentedLagrangianCoupling(Coupling):
    """d, lambda and r beside the flow: the stress of step 1 in the forms, the ALG2
    iteration for the step, d, lambda and r kept at the step's start (restored on a
    rejection), checkpointed and carried through a remesh."""

    name = "augmented-lagrangian"

    def __init__(self, mesh: ngs.Mesh, augmentation: float) -> None:
        self.strain = ngs.GridFunction(tensor_space(mesh))       # d
        self.multiplier = ngs.GridFunction(tensor_space(mesh))   # lambda
        self.augmentation = ngs.Parameter(augmentation)           # r, balanced
        self.augmented: AugmentedLagrangian | None = None         # once bound

    def stress(self, stress: StressTerm, law: Any) -> StressTerm:
        if not isinstance(law, DruckerPrager):
            raise ValueError("the augmented Lagrangian method needs the Drucker-Prager law")
        return AugmentedStress(law, self.augmentation, self.strain, self.multiplier)

    def bind(self, flow: Flow) -> None:
        self.augmented = AugmentedLagrangian(flow.rheology, self.augmentation, flow.nonlinear,
                                             self.strain, self.multiplier)

    def _iteration(self) -> AugmentedLagrangian:
        assert self.augmented is not None, "bind the coupling to its flow first"
        return self.augmented

    def iteration(self, default: Iteration) -> Iteration:
        return self._iteration().solve

    def accept(self, dt: float) -> None:
        self._iteration().remember()

    def reject(self) -> None:
        self._iteration().restore()

    def share(self) -> Share:
        return {"strain": array("strain dofs"), "multiplier": array("strain dofs"),
                "augmentation": may_lack(number(0.0, above=True))}

    def save(self) -> dict[str, object]:
        return {"strain": self.strain.vec.FV().NumPy().copy(),
                "multiplier": self.multiplier.vec.FV().NumPy().copy(),
                "augmentation": self.augmentation.Get()}

    def restore(self, state: Mapping[str, object]) -> None:
        assign(self.strain.vec.FV().NumPy(), state["strain"], "the saved strain rate d")
        assign(self.multiplier.vec.FV().NumPy(), state["multiplier"],
               "the saved multiplier lambda")
        if "augmentation" in state:
            self.augmentation.Set(float(state["augmentation"]))  # type: ignore[arg-type]
        self._iteration().remember()

    def inherit(self, old: Coupling, carry: Carriers) -> None:
        assert isinstance(old, AugmentedLagrangianCoupling)
        carry.tensor(old.strain, self.strain)
        carry.tensor(old.multiplier, self.multiplier)
        self.augmentation.Set(old.augmentation.Get())
        self._iteration().remember()
