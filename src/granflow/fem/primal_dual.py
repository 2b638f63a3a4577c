"""A primal-dual iteration for the regularised law (2.13): Picard (3.2) plus the Newton
correction of a dual variable, after Chan, Golub & Mulet (1999) for total variation and
De los Reyes & Gonzalez-Andrade (2010) for Bingham flows.

Write the plastic part of (2.13) as kappa lambda with the dual variable
lambda = Du / r(Du), r = sqrt(|Du|^2 + eps^2), so |lambda| < 1. Newton's linearisation of
r lambda - Du = 0 at (u_k, lambda_k) gives, pointwise,

    lambda_{k+1} = Du_{k+1} / r_k - lambda_k (Du_k : (Du_{k+1} - Du_k)) / r_k^2,

and putting it into the momentum equation adds to the fixed-point matrix of (3.2)

    - kappa_k / r_k^2 sym[(Du_k : Du)(lambda_k : Dv)]   (left)
    - kappa_k / r_k^2 |Du_k|^2 (lambda_k : Dv)          (right-hand side).

With lambda_k = Du_k / r_k this is Newton's tangent, nearly singular where |Du| ~ eps;
with lambda_k carried as its own variable and projected onto |lambda| <= 1, the matrix
stays positive and the iteration converges where the plain fixed point crawls (the rigid
zones of a mass coming to rest). Symmetrising (Chan-Golub-Mulet) keeps the matrix's
structure. At convergence lambda = Du / r and the discrete solution is the one of (3.2).
kappa is taken at the iterate's pressure as in (3.2); the wall friction stays Picard.

lambda lives at the quadrature points of the viscoplastic term (the three edge midpoints,
``VISCOPLASTIC_DX``) in an ``IntegrationRuleSpace``, so no projection enters.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from ngsolve.comp import IntegrationRuleSpace

from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.forms import strain_rate
from granflow.physics import DruckerPrager

COMPONENTS = ((0, 0), (0, 1), (1, 1))   # a symmetric 2x2 tensor stored as xx, xy, yy
WEIGHTS = np.array([1.0, 2.0, 1.0])      # Frobenius A : B of two tensors so stored


class DualVariable:
    """lambda at the quadrature points, the correction it adds to (3.2), and its update."""

    def __init__(self, mesh: ngs.Mesh, rheology: DruckerPrager,
                 iterate: ngs.GridFunction) -> None:
        self.space = IntegrationRuleSpace(mesh, order=1)   # the 3 edge midpoints
        self.dx = ngs.dx(intrules=self.space.GetIntegrationRules())
        self.eps = rheology.eps
        self.iterate = iterate
        # xx, xy, yy as scalar fields (a vector-valued IntegrationRuleSpace did not
        # interpolate pointwise in NGSolve 6.2.2608)
        self.parts = [ngs.GridFunction(self.space) for _ in range(3)]
        a, b, c = self.parts
        self.lam = ngs.CF((a, b, b, c), dims=(2, 2))
        u_k, p_k = iterate.components
        self.du_k = strain_rate(u_k)
        self.r_sq = ngs.InnerProduct(self.du_k, self.du_k) + rheology.eps**2
        self.kappa = rheology.yield_stress(p_k, NGSOLVE_OPS)
        # Du at the quadrature points as a matrix on the (u, p) vector: the form
        # sum_e w |J| Du w_i divided by each point's weight w |J| (reassembled each step:
        # the mesh moves)
        (u, _), test = iterate.space.TrialFunction(), self.space.TestFunction()
        self._strain_forms = []
        for i, j in COMPONENTS:
            form = ngs.BilinearForm(trialspace=iterate.space, testspace=self.space)
            form += strain_rate(u)[i, j] * test * self.dx
            self._strain_forms.append(form)
        self._weights = ngs.LinearForm(self.space)
        self._weights += test * self.dx
        self._tmp = self._weights.vec.CreateVector()
        self._w = np.ones(len(self._tmp))
        self._du_k = np.zeros((len(self._tmp), 3))

    def forms(self, space: ngs.FESpace) -> tuple[ngs.BilinearForm, ngs.LinearForm]:
        """The correction's matrix and right-hand side (module docstring), at the iterate."""
        (u, _), (v, _) = space.TnT()
        du, dv = strain_rate(u), strain_rate(v)
        coupling = 0.5 * (ngs.InnerProduct(self.du_k, du) * ngs.InnerProduct(self.lam, dv)
                          + ngs.InnerProduct(self.lam, du) * ngs.InnerProduct(self.du_k, dv))
        matrix = ngs.BilinearForm(space)
        matrix += -self.kappa / self.r_sq * coupling * self.dx
        rhs = ngs.LinearForm(space)
        rhs += (-self.kappa / self.r_sq * ngs.InnerProduct(self.du_k, self.du_k)
                * ngs.InnerProduct(self.lam, dv) * self.dx)
        return matrix, rhs

    def prepare(self) -> None:
        """Start of a step, on the moved mesh: the strain-rate operator."""
        for form in self._strain_forms:
            form.Assemble()
        self._weights.Assemble()
        self._w = self._weights.vec.FV().NumPy().copy()

    def start(self) -> None:
        """Switch the correction on at the current iterate with lambda = 0: its first
        iteration is the plain fixed point, which gives the first dual estimate."""
        self._du_k = self._strain(self.iterate.vec)
        self._set(np.zeros_like(self._du_k))

    def update(self, solution: ngs.BaseVector) -> None:
        """lambda_{k+1} from u_k (the iterate) and u_{k+1} (``solution``), projected
        onto |lambda| <= 1."""
        du_next = self._strain(solution)
        r_sq = (self._du_k**2) @ WEIGHTS + self.eps**2
        lam = np.column_stack([part.vec.FV().NumPy() for part in self.parts])
        change = ((du_next - self._du_k) * self._du_k) @ WEIGHTS
        new = du_next / np.sqrt(r_sq)[:, None] - lam * (change / r_sq)[:, None]
        new /= np.maximum(np.sqrt((new**2) @ WEIGHTS), 1.0)[:, None]
        self._set(new)
        self._du_k = du_next

    def _strain(self, vec: ngs.BaseVector) -> np.ndarray:
        """(xx, xy, yy) of Du at the quadrature points, from a (u, p) vector."""
        out = np.empty((len(self._tmp), 3))
        for k, form in enumerate(self._strain_forms):
            self._tmp.data = form.mat * vec
            out[:, k] = self._tmp.FV().NumPy()
        return out / self._w[:, None]

    def _set(self, lam: np.ndarray) -> None:
        for k, part in enumerate(self.parts):
            part.vec.FV().NumPy()[:] = lam[:, k]
