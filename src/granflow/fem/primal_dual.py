"""A primal-dual iteration for the regularised law (2.13): Picard (3.2) plus the Newton
correction of a dual variable, after Chan, Golub & Mulet (1999) for total variation and
De los Reyes & Gonzalez-Andrade (2010) for Bingham flows.

Write the plastic part of (2.13) as kappa lambda with the dual variable
lambda = Du / r(Du), r = sqrt(|Du|^2 + eps^2), so |lambda| < 1. Newton's linearisation of
r lambda - Du = 0 at (u_k, lambda_k) gives, pointwise,

    lambda_{k+1} = Du_{k+1} / r_k - lambda_k (Du_k : (Du_{k+1} - Du_k)) / r_k^2,

and putting it into the momentum equation, with kappa(p) linearised at p_k as well
(kappa(p) lambda ~ kappa_k lambda_{k+1} + kappa'(p_k)(p - p_k) lambda_k, kappa' =
sqrt(2) mu_s where p_k > 0), adds to the fixed-point matrix of (3.2)

    - kappa_k / r_k^2 sym[(Du_k : Du)(lambda_k : Dv)] + kappa'(p_k) p (lambda_k : Dv)   (left)
    - kappa_k / r_k^2 |Du_k|^2 (lambda_k : Dv) + kappa'(p_k) p_k (lambda_k : Dv)       (right).

With lambda_k = Du_k / r_k the first term would be Newton's tangent, nearly singular where
|Du| ~ eps; with lambda_k carried as its own variable and projected onto |lambda| <= 1 the
matrix stays positive (symmetrising, after Chan-Golub-Mulet, keeps its structure). The
pressure term matters at the yield limit, where the yield stress and the pressure are
coupled: without it, the corrected iteration overshot and was undone on a creeping
deposit; with it, it converged there in 87 iterations a step against 216 for (3.2)
(docs/verification.md). At convergence lambda = Du / r and both additions vanish against
their right-hand sides: the discrete solution is the one of (3.2). The wall friction
stays Picard.

lambda lives at the quadrature points of the viscoplastic term (the three edge midpoints,
``VISCOPLASTIC_RULES``) in an ``IntegrationRuleSpace``, so no projection enters.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np
from ngsolve.comp import IntegrationRuleSpace

from granflow.fem.coupling import Coupling, Flow, Site
from granflow.fem.forms import strain_rate
from granflow.physics import DruckerPrager, Rheology
from granflow.physics.composite import blended, cell_share, simple_laws

COMPONENTS = ((0, 0), (0, 1), (1, 1))   # a symmetric 2x2 tensor stored as xx, xy, yy
WEIGHTS = np.array([1.0, 2.0, 1.0])      # Frobenius A : B of two tensors so stored


class PointTensor:
    """A symmetric 2x2 tensor field given by its values at the quadrature points: three
    scalar fields of an IntegrationRuleSpace (xx, xy, yy; a vector-valued one did not
    interpolate pointwise in NGSolve 6.2.2608)."""

    def __init__(self, space: ngs.FESpace) -> None:
        self.parts = [ngs.GridFunction(space) for _ in range(3)]
        a, b, c = self.parts
        self.cf = ngs.CF((a, b, b, c), dims=(2, 2))

    def get(self) -> np.ndarray:
        return np.column_stack([part.vec.FV().NumPy() for part in self.parts])

    def set(self, values: np.ndarray) -> None:
        for k, part in enumerate(self.parts):
            part.vec.FV().NumPy()[:] = values[:, k]


class DualVariable:
    """lambda at the quadrature points, the correction it adds to (3.2), and its update.

    The correction's coefficients are kept as point fields computed with numpy,
    alpha = -kappa_k Du_k / r_k^2, beta = kappa'(p_k) lambda and
    gamma = (alpha : Du_k + kappa'(p_k) p_k) lambda, so that assembling it costs lookups
    rather than the law: matrix sym[(alpha : Du)(lambda : Dv)] + p beta : Dv, right-hand
    side gamma : Dv.
    """

    def __init__(self, mesh: ngs.Mesh, rheology: Rheology,
                 iterate: ngs.GridFunction) -> None:
        self.space = IntegrationRuleSpace(mesh, order=1)   # the 3 edge midpoints
        self.dx = ngs.dx(intrules=self.space.GetIntegrationRules())
        self.rheology, self.iterate = rheology, iterate
        self.lam, self.alpha, self.gamma = (PointTensor(self.space) for _ in range(3))
        self.beta = PointTensor(self.space)   # kappa'(p_k) lambda_k: Newton in p
        # Du and p at the quadrature points as matrices on the (u, p) vector: the forms
        # sum_e w |J| Du w_i (and p w_i) divided by each point's weight w |J|
        # (reassembled each step: the mesh moves)
        (u, p), test = iterate.space.TrialFunction(), self.space.TestFunction()
        self._point_forms = []
        for value in [strain_rate(u)[i, j] for i, j in COMPONENTS] + [p]:
            form = ngs.BilinearForm(trialspace=iterate.space, testspace=self.space)
            form += value * test * self.dx
            self._point_forms.append(form)
        self._weights = ngs.LinearForm(self.space)
        self._weights += test * self.dx
        self._tmp = self._weights.vec.CreateVector()
        self._w = np.ones(len(self._tmp))
        self._du_k = np.zeros((len(self._tmp), 3))
        self._p_k = np.zeros(len(self._tmp))
        self._operators_current = False

    def forms(self, space: ngs.FESpace) -> tuple[ngs.BilinearForm, ngs.LinearForm]:
        """The correction's matrix and right-hand side (module docstring), at the iterate."""
        (u, p), (v, _) = space.TnT()
        du, dv = strain_rate(u), strain_rate(v)
        alpha, lam = self.alpha.cf, self.lam.cf
        matrix = ngs.BilinearForm(space)
        integrand = 0.5 * (ngs.InnerProduct(alpha, du) * ngs.InnerProduct(lam, dv)
                           + ngs.InnerProduct(lam, du) * ngs.InnerProduct(alpha, dv))
        matrix += integrand.Compile() * self.dx      # ~20 % faster assembly, same matrix
        matrix += p * ngs.InnerProduct(self.beta.cf, dv) * self.dx
        rhs = ngs.LinearForm(space)
        rhs += ngs.InnerProduct(self.gamma.cf, dv) * self.dx
        return matrix, rhs

    def prepare(self) -> None:
        """Start of a step (the mesh has moved): the point operators are out of date.
        They are reassembled by ``start``, only in the steps that use the correction."""
        self._operators_current = False

    def start(self) -> None:
        """Switch the correction on at the current iterate with lambda = 0: its first
        iteration is the plain fixed point, which gives the first dual estimate."""
        if not self._operators_current:
            for form in self._point_forms:
                form.Assemble()
            self._weights.Assemble()
            self._w = self._weights.vec.FV().NumPy().copy()
            self._operators_current = True
        self._du_k, self._p_k = self._at_points(self.iterate.vec)
        self.lam.set(np.zeros_like(self._du_k))
        self._coefficients()

    def update(self, solution: ngs.BaseVector) -> None:
        """lambda_{k+1} from u_k (the iterate) and u_{k+1} (``solution``), projected
        onto |lambda| <= 1; ``solution`` becomes the iterate."""
        du_next, p_next = self._at_points(solution)
        r_sq = (self._du_k**2) @ WEIGHTS + self.rheology.eps**2
        change = ((du_next - self._du_k) * self._du_k) @ WEIGHTS
        new = du_next / np.sqrt(r_sq)[:, None] - self.lam.get() * (change / r_sq)[:, None]
        new /= np.maximum(np.sqrt((new**2) @ WEIGHTS), 1.0)[:, None]
        self.lam.set(new)
        self._du_k, self._p_k = du_next, p_next
        self._coefficients()

    def _coefficients(self) -> None:
        """alpha, beta and gamma at the iterate (u_k, p_k) and lambda_k."""
        r_sq = (self._du_k**2) @ WEIGHTS + self.rheology.eps**2
        kappa_1 = self._yield_slope()                 # sqrt(2) mu_s: kappa = kappa_1 [p]_+
        alpha = -(kappa_1 * np.maximum(self._p_k, 0.0) / r_sq)[:, None] * self._du_k
        self.alpha.set(alpha)
        lam = self.lam.get()
        slope = np.where(self._p_k > 0, kappa_1, 0.0)  # kappa'(p_k)
        self.beta.set(slope[:, None] * lam)
        self.gamma.set(((alpha * self._du_k) @ WEIGHTS + slope * self._p_k)[:, None] * lam)

    def _yield_slope(self) -> float | np.ndarray:
        """kappa / [p]_+ = sqrt(2) mu (2.4) at the quadrature points: one number, or per
        point for a column over a layer of another Drucker-Prager material (blended with
        the triangles' fractions), a hysteretic friction (blended with the triangles'
        mobilisation) or a packing's friction tan(psi) (at the iterate)."""
        return _yield_slope(self.rheology, lambda: (self._du_k**2) @ WEIGHTS, self._p_k)

    def _at_points(self, vec: ngs.BaseVector) -> tuple[np.ndarray, np.ndarray]:
        """(xx, xy, yy) of Du and p at the quadrature points, from a (u, p) vector."""
        out = np.empty((len(self._tmp), 4))
        for k, form in enumerate(self._point_forms):
            self._tmp.data = form.mat * vec
            out[:, k] = self._tmp.FV().NumPy()
        out /= self._w[:, None]
        return out[:, :3], out[:, 3]


def _yield_slope(law: Rheology, strain_rate_sq: Callable[[], np.ndarray],
                 pressure: np.ndarray) -> float | np.ndarray:
    """sqrt(2) mu of a Drucker-Prager law, or per quadrature point (three per triangle) of
    a blended one; a law wrapping another (a packing's) adds its friction at the points
    (``yield_slope_extra`` at |Du|^2 and p), the total kept at least 0."""
    return np.maximum(blended(  # type: ignore[no-any-return]
        law, _drucker_prager_slope, lambda composite: np.repeat(cell_share(composite), 3),
        added=lambda wrapper: wrapper.yield_slope_extra(strain_rate_sq(), pressure)), 0.0)


def _drucker_prager_slope(law: Rheology) -> float:
    assert isinstance(law, DruckerPrager)
    return law.yield_stress(1.0)        # type: ignore[no-any-return]


def drucker_prager(law: Rheology) -> bool:
    """The Drucker-Prager law (2.13), alone, as both materials of a column over a layer,
    with a hysteretic friction or a packing's: what the primal-dual correction is built
    for."""
    return all(isinstance(part, DruckerPrager) for part in simple_laws(law))


@dataclass(frozen=True)
class PrimalDualSpec:
    """``numerics.linearization = "primal-dual"``: the dual correction joins (3.2)."""

    def build(self, site: Site, fields: Mapping[str, Any]) -> PrimalDualCoupling:
        return PrimalDualCoupling()


class PrimalDualCoupling(Coupling):
    """The dual variable lambda beside the fixed-point iteration: built for the plane
    Drucker-Prager law (2 x 2 tensors); with another law (mu(I)), in axisymmetry or in 3D
    "primal-dual" is the plain iteration (3.2) (docs/parameters.md). It holds no state
    across steps."""

    name = "primal-dual"

    def corrections(self, flow: Flow) -> tuple[DualVariable, ...]:
        plane = flow.coordinates.dimension == 2 and not flow.coordinates.axisymmetric
        if not drucker_prager(flow.rheology) or not plane:
            return ()
        return (DualVariable(flow.mesh, flow.rheology, flow.solution),)
