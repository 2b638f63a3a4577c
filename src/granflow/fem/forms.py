"""Weak forms of one fixed-point iteration of the momentum and mass equations (3.2).

The forms are built once; their coefficients (the previous iterate, the previous time
step, the mesh velocity, the time step) are NGSolve GridFunctions and Parameters, so an
iteration only reassembles. Sign convention: N is the outward unit normal.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import ngsolve as ngs

from granflow.fem.engine import NGSOLVE_OPS
from granflow.physics import CoulombFriction, DruckerPrager


@dataclass(frozen=True)
class FrictionWall:
    """A boundary region with Coulomb friction (2.8) and the non-penetration penalty (2.7)."""

    region: str
    law: CoulombFriction


def strain_rate(u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """Du = (grad u + grad u^T) / 2."""
    return ngs.Sym(ngs.Grad(u))


def frobenius(tensor: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """|D| without the factor 1/2 (paper, after (2.2))."""
    return ngs.sqrt(ngs.InnerProduct(tensor, tensor))


@dataclass
class MomentumForms:
    """Bilinear and linear forms of (3.2a)-(3.2b) for one Picard iteration."""

    a: ngs.BilinearForm
    f: ngs.LinearForm
    effective_viscosity: ngs.CoefficientFunction


def build_momentum_forms(
    space: ngs.FESpace,
    iterate: ngs.GridFunction,
    previous: ngs.GridFunction,
    mesh_velocity: ngs.GridFunction,
    rheology: DruckerPrager,
    density: float,
    body_force: tuple[float, float],
    dt: ngs.Parameter,
    walls: Sequence[FrictionWall] = (),
    penalty: float = 0.0,
) -> MomentumForms:
    """Assemble-ready forms of (3.2a)-(3.2b) linearised at ``iterate`` = (u^k, p^k).

    ``previous`` holds u^n carried by the moving nodes (u^n o A^{-1}); ``mesh_velocity``
    is w^n, also carried by the nodes.
    """
    mesh = space.mesh
    (u, p), (v, q) = space.TnT()
    u_k, p_k = iterate.components
    u_n = previous.components[0]
    rho = density

    du_k = strain_rate(u_k)
    m_k = rheology.effective_viscosity(frobenius(du_k), p_k, NGSOLVE_OPS)  # (2.13) at u^k

    a = ngs.BilinearForm(space)
    a += rho / dt * u * v * ngs.dx                                          # (3.2a) time
    a += rho * (ngs.Grad(u) * (u_k - mesh_velocity)) * v * ngs.dx           # ALE convection
    a += m_k * ngs.InnerProduct(strain_rate(u), strain_rate(v)) * ngs.dx    # regularised law
    a += (-p * ngs.div(v) - q * ngs.div(u)) * ngs.dx                        # (3.2a)-(3.2b)

    if walls:
        n = ngs.specialcf.normal(mesh.dim)
        u_t = u - (u * n) * n
        v_t = v - (v * n) * n
        uk_t = u_k - (u_k * n) * n
        du_k_bnd = ngs.BoundaryFromVolumeCF(du_k)
        m_k_bnd = rheology.effective_viscosity(frobenius(du_k_bnd), p_k, NGSOLVE_OPS)
        sigma_n = m_k_bnd * ngs.InnerProduct(du_k_bnd * n, n)             # sigma'_N at u^k
        for wall in walls:
            drag = wall.law.drag_coefficient(ngs.Norm(uk_t), p_k - sigma_n, NGSOLVE_OPS)
            region = mesh.Boundaries(wall.region)
            a += drag * u_t * v_t * ngs.ds(definedon=region)               # Coulomb (2.17a)
            a += penalty * (u * n) * (v * n) * ngs.ds(definedon=region)    # u.N = 0 (2.7)

    f = ngs.LinearForm(space)
    f += rho / dt * u_n * v * ngs.dx
    f += rho * ngs.CF(body_force) * v * ngs.dx                              # rho f, (2.1a)
    return MomentumForms(a=a, f=f, effective_viscosity=m_k)
