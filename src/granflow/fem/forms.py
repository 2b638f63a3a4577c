"""Terms of the momentum and mass equations (2.17), (3.2), each stated once for Picard
and Newton.

A term gives its contribution to the residual R(u, p; v, q) of one time step.
Its nonlinear coefficients (effective viscosity, friction drag, convecting velocity) are
evaluated at a *linearisation point* (u_lin, p_lin):

- Newton passes the unknowns themselves, so the residual is fully nonlinear and NGSolve
  differentiates it symbolically (the consistent tangent with respect to u and p);
- Picard (3.2) passes the current iterate (u^k, p^k), which makes the residual affine in
  (u, p): its linearisation is exactly the matrix of the fixed-point iteration.

Sign convention: N is the outward unit normal. Norms are Frobenius, no factor 1/2.
"""

from __future__ import annotations

import dataclasses
import functools
import operator
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import ngsolve as ngs

from granflow.fem.engine import NGSOLVE_OPS, read_on_walls
from granflow.fem.measure import PLANE, Coordinates
from granflow.physics import Rheology, SideWallFriction
from granflow.physics.ops import Ops


def strain_rate(u: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """Du = (grad u + grad u^T) / 2 in plane strain (``fem/measure.py`` for axisymmetry)."""
    return PLANE.strain_rate(u)


def frobenius(tensor: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """|D| without the factor 1/2 (paper, after (2.2))."""
    return ngs.sqrt(ngs.InnerProduct(tensor, tensor))


def tangential(u: ngs.CoefficientFunction, n: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
    """u_T = u - (u.N) N."""
    return u - (u * n) * n


# The quadrature of the viscoplastic term, fixed so that Picard and Newton integrate the
# same discrete law: NGSolve would pick order 2 (3 points) for the Picard form, where the
# coefficient is a known field, and order 4 for Newton's, where it depends on the unknown.
# Order 2 is what the verified runs (docs/verification.md) used; tetrahedra (3D) alike.
VISCOPLASTIC_RULES = {ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, 2),
                      ngs.TET: ngs.IntegrationRule(ngs.TET, 2)}
# In r-z the integrand r Du : Dv has degree 3 plus the hoop part u_r v_r / r: the 3-point
# rule leaves the viscous matrix singular (tests/verification/test_axisymmetric_stokes.py),
# a 6-point rule of order 4 does not.
AXISYMMETRIC_VISCOPLASTIC_RULES = {ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, 4)}


@dataclass(frozen=True)
class Symbols:
    """Unknowns (u, p), tests (v, q), the point (u_lin, p_lin) where coefficients live, and
    the coordinates that give every term its measure, strain rate and divergence."""

    u: ngs.CoefficientFunction
    p: ngs.CoefficientFunction
    v: ngs.CoefficientFunction
    q: ngs.CoefficientFunction
    u_lin: ngs.CoefficientFunction
    p_lin: ngs.CoefficientFunction
    coords: Coordinates = PLANE


class Term(Protocol):
    """One term of the residual R = lhs - rhs; ``rhs`` holds the parts free of (u, p).

    A term whose ``lhs`` does not read (u_lin, p_lin) sets ``step_constant = True``: the
    fixed-point iteration assembles it once per step instead of once per iteration. One that
    reads the volume on a boundary (``BoundaryFromVolumeCF``) sets ``compiled = False``:
    NGSolve's compiler prints a line per such node (and computes the same matrix).
    """

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals | None: ...
    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals | None: ...


class WallLaw(Protocol):
    """What a wall exerts along itself: the factor c of the traction -c u_T from |u_T|^2 and
    the normal load (``physics/friction.py: CoulombFriction``, ``physics/bed.py``)."""

    def drag_coefficient_sq(self, slip_sq: ngs.CoefficientFunction,
                            normal_stress: ngs.CoefficientFunction,
                            ops: Ops) -> ngs.CoefficientFunction: ...


class StressTerm(Term, Protocol):
    """The term of the deviatoric stress; the wall friction reads sigma' from it."""

    def wall_deviatoric(self, u_lin: ngs.CoefficientFunction, p_lin: ngs.CoefficientFunction,
                        frozen: bool) -> ngs.CoefficientFunction: ...


class _LhsOnly:
    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals | None:
        return None


@dataclass(frozen=True)
class Inertia:
    """rho (u - u^n o A^-1) / dt . v (3.2a); ``previous`` is carried by the moving nodes."""

    density: float | ngs.CoefficientFunction
    dt: ngs.Parameter
    previous: ngs.CoefficientFunction
    step_constant = True

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(self.density / self.dt * s.u * s.v)

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(self.density / self.dt * self.previous * s.v)


@dataclass(frozen=True)
class BackwardDifferenceInertia:
    """rho (a0 u - h) / dt . v: the inertia of a multistep scheme (``fem/time_scheme.py``),
    h = a1 u^n - a2 u^{n-1} its known history carried by the moving nodes."""

    density: float | ngs.CoefficientFunction
    dt: ngs.Parameter
    a0: ngs.Parameter
    history: ngs.CoefficientFunction
    step_constant = True

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(self.density * self.a0 / self.dt * s.u * s.v)

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(self.density / self.dt * self.history * s.v)


@dataclass(frozen=True)
class Convection(_LhsOnly):
    """rho [(u_lin - w) . grad] u . v: ALE convection with the mesh velocity w (3.2a)."""

    density: float | ngs.CoefficientFunction
    mesh_velocity: ngs.CoefficientFunction

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(self.density * (ngs.Grad(s.u) * (s.u_lin - self.mesh_velocity)) * s.v)


@dataclass(frozen=True)
class ViscoplasticStress(_LhsOnly):
    """(2 eta + kappa(p_lin) / sqrt(|D u_lin|^2 + eps^2)) Du : Dv, the regularised law
    (2.13) with kappa = sqrt(2) mu_s [p]_+ (2.4), or with mu(I) in place of mu_s."""

    rheology: Rheology
    coords: Coordinates = PLANE

    def viscosity(self, u_lin: ngs.CoefficientFunction,
                  p_lin: ngs.CoefficientFunction) -> ngs.CoefficientFunction:
        square = self.coords.strain_rate_sq(u_lin)
        return self.rheology.effective_viscosity_sq(square, p_lin, NGSOLVE_OPS)

    def wall_deviatoric(self, u_lin: ngs.CoefficientFunction, p_lin: ngs.CoefficientFunction,
                        frozen: bool) -> ngs.CoefficientFunction:
        """The in-plane block of sigma' = m Du at (u_lin, p_lin) on a wall (what loads the
        wall friction; m sees the whole |Du|, hoop part included); a known (frozen) strain
        rate is traced from the volume before m is formed."""
        du = strain_rate(u_lin)              # the in-plane block, all a wall's normal sees
        law = self.rheology
        if frozen:
            du, law = ngs.BoundaryFromVolumeCF(du), read_on_walls(law)
        square = ngs.InnerProduct(du, du)
        if self.coords.axisymmetric:         # |Du|^2 has the hoop part, continuous across
            square = square + self.coords.hoop_strain(u_lin) ** 2
        m = law.effective_viscosity_sq(square, p_lin, NGSOLVE_OPS)
        return m * du

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        m = self.viscosity(s.u_lin, s.p_lin)
        c = s.coords
        rules = AXISYMMETRIC_VISCOPLASTIC_RULES if c.axisymmetric else VISCOPLASTIC_RULES
        # in parts (r-z: in-plane and hoop): much faster to assemble than the 3 x 3 form
        parts = [c.dx(m * part, intrules=rules) for part in c.strain_product_parts(s.u, s.v)]
        return functools.reduce(operator.add, parts)


@dataclass(frozen=True)
class Incompressibility(_LhsOnly):
    """-p div v - q div u: the pressure and the constraint (3.2a)-(3.2b)."""

    step_constant = True

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(-s.p * s.coords.div(s.v) - s.q * s.coords.div(s.u))


@dataclass(frozen=True)
class BodyForce:
    """rho f . v on the right-hand side: gravity in the bed frame (2.1a)."""

    density: float | ngs.CoefficientFunction
    force: tuple[float, ...]             # (X, Z), or (X, Y, Z) in 3D

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals | None:
        return None

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        return s.coords.dx(self.density * ngs.CF(self.force) * s.v)


@dataclass(frozen=True)
class FrictionWall:
    """A boundary region with Coulomb friction (2.8) (or another law along it: a bed's,
    ``physics/bed.py``) and the non-penetration penalty (2.7).

    ``normal_load`` is what presses the material on the wall in the friction law:
    "pressure", the paper's pointwise [p - sigma'_N]_+ of (3.2a), or "reaction", the
    normal traction the penalty actually exerts, [xi u.N]_+, whose integral over the wall
    is the discrete normal force (the pointwise pressure under-loads the corners of a
    sliding block by 2-4 %, tests/verification/test_collapse.py).
    """

    region: str
    law: WallLaw
    normal_load: str = "pressure"
    velocity: ngs.CoefficientFunction | None = None   # a moving wall's (a gate), tangential
    penalised: bool = True    # False: u.N = 0 is held by the space (``fem/spaces.py``)

    def on_law(self, rheology: Rheology) -> FrictionWall:
        """This wall for a flow of ``rheology``: a law that is the material's own (it has
        ``for_law``, a recipe frozen before the law exists: ``scenarios/bed.py``) made of
        it, any other as it is."""
        for_law = getattr(self.law, "for_law", None)
        return self if for_law is None else dataclasses.replace(self, law=for_law(rheology))


@dataclass(frozen=True)
class CoulombWallFriction:
    """mu [p - sigma'_N]_+ u_T . v_T / sqrt(|u_T|^2 + eps_f^2) on one wall (2.17a), the
    drag and the normal load taken at (u_lin, p_lin) as in (3.2a). On a wall moving at V
    along itself (a gate) the slip is u_T - V_T: the drag times V_T . v_T is on the right.

    sigma'_N = (sigma' N) . N needs the strain rate of the volume element at the wall,
    hence a boundary skeleton integral.
    """

    wall: FrictionWall
    stress: StressTerm
    penalty: float = 0.0     # xi of NormalPenalty, for normal_load = "reaction"
    compiled = False         # sigma'_N of a frozen iterate is read from the volume

    @property
    def rhs_reads_iterate(self) -> bool:
        """A moving wall's right-hand side has the drag at the iterate (Picard assembles
        it at every iteration)."""
        return self.wall.velocity is not None

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals | None:
        if self.wall.velocity is None:
            return None
        n = ngs.specialcf.normal(mesh.dim)
        drag, skeleton = self._drag(s, mesh)
        integrand = drag * tangential(self.wall.velocity, n) * tangential(s.v, n)
        region = mesh.Boundaries(self.wall.region)
        return s.coords.ds(integrand, skeleton=skeleton, definedon=region)

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        n = ngs.specialcf.normal(mesh.dim)
        region = mesh.Boundaries(self.wall.region)
        drag, skeleton = self._drag(s, mesh)
        integrand = drag * tangential(s.u, n) * tangential(s.v, n)
        if skeleton:
            return s.coords.ds(integrand, skeleton=True, definedon=region)
        return s.coords.ds(integrand, definedon=region)

    def _drag(self, s: Symbols, mesh: ngs.Mesh) -> tuple[ngs.CoefficientFunction, bool]:
        """The drag coefficient at (u_lin, p_lin), and whether it needs a skeleton
        integral (it reads the volume's strain rate)."""
        n = ngs.specialcf.normal(mesh.dim)
        frozen = s.u_lin is not s.u
        moving = s.u_lin if self.wall.velocity is None else s.u_lin - self.wall.velocity
        slip = tangential(moving, n)
        skeleton = False
        if not getattr(self.wall.law, "reads_load", True):     # a no-slip penalty
            load = ngs.CF(0.0)
        elif self.wall.normal_load == "reaction":
            load = self.penalty * (s.u_lin * n)
        else:
            sigma = self.stress.wall_deviatoric(s.u_lin, s.p_lin, frozen)
            load = s.p_lin - ngs.InnerProduct(sigma * n, n)
            skeleton = not frozen
        return self.wall.law.drag_coefficient_sq(slip * slip, load, NGSOLVE_OPS), skeleton


@dataclass(frozen=True)
class NormalPenalty(_LhsOnly):
    """xi (u . N)(v . N): u . N = 0 on a wall, imposed weakly (2.7), (3.2a)."""

    region: str
    penalty: float
    step_constant = True

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        n = ngs.specialcf.normal(mesh.dim)
        return s.coords.ds(self.penalty * (s.u * n) * (s.v * n),
                           definedon=mesh.Boundaries(self.region))


@dataclass(frozen=True)
class ChannelSideWalls(_LhsOnly):
    """(2 mu_w / W) [p_lin]_+ u . v / sqrt(|u_lin|^2 + eps_f^2): the Coulomb drag of the
    side walls of a channel of width W, a body force in the 2D momentum equation."""

    law: SideWallFriction

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        drag = self.law.drag_coefficient_sq(s.u_lin * s.u_lin, s.p_lin, NGSOLVE_OPS)
        return s.coords.dx(drag * s.u * s.v)


@dataclass(frozen=True)
class SurfaceTraction:
    """gamma v . N on the free surface: the right-hand side of (2.17a) with (2.11), gamma
    the numerical surface tension gamma_0 C of (3.8), a known field during the step."""

    region: str
    gamma: ngs.CoefficientFunction

    def lhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals | None:
        return None

    def rhs(self, s: Symbols, mesh: ngs.Mesh) -> ngs.SumOfIntegrals:
        n = ngs.specialcf.normal(mesh.dim)
        return s.coords.ds(self.gamma * (s.v * n), definedon=mesh.Boundaries(self.region))


def momentum_terms(*, density: float | ngs.CoefficientFunction, inertia: Term,
                   mesh_velocity: ngs.CoefficientFunction, rheology: Rheology,
                   body_force: tuple[float, ...], walls: Sequence[FrictionWall] = (),
                   penalty: float = 0.0,
                   surface_traction: SurfaceTraction | None = None,
                   side_walls: SideWallFriction | None = None,
                   stress: StressTerm | None = None,
                   coords: Coordinates = PLANE) -> list[Term]:
    """The terms of (3.2a)-(3.2b) for a flow with the given walls (and surface tension,
    and the drag of a channel's side walls); ``inertia`` is the time scheme's
    (``fem/time_scheme.py``), ``stress`` replaces the regularised law (the augmented
    Lagrangian's)."""
    stress = stress or ViscoplasticStress(rheology, coords)
    terms: list[Term] = [inertia, Convection(density, mesh_velocity),
                         stress, Incompressibility(), BodyForce(density, body_force)]
    for wall in (w.on_law(rheology) for w in walls):
        terms.append(CoulombWallFriction(wall, stress, penalty))
        if wall.penalised:
            terms.append(NormalPenalty(wall.region, penalty))
    if surface_traction is not None:
        terms.append(surface_traction)
    if side_walls is not None:
        terms.append(ChannelSideWalls(side_walls))
    return terms


def _symbols(space: ngs.FESpace, linearisation: ngs.GridFunction | None,
             coords: Coordinates) -> Symbols:
    (u, p), (v, q) = space.TnT()
    if linearisation is None:
        return Symbols(u=u, p=p, v=v, q=q, u_lin=u, p_lin=p, coords=coords)
    u_lin, p_lin = linearisation.components
    return Symbols(u=u, p=p, v=v, q=q, u_lin=u_lin, p_lin=p_lin, coords=coords)


def residual_form(space: ngs.FESpace, terms: Sequence[Term],
                  coords: Coordinates = PLANE) -> ngs.BilinearForm:
    """R(x; v, q) = lhs - rhs with every coefficient at the unknowns (Newton): ``Apply``
    gives R(x), ``AssembleLinearization`` the consistent tangent dR/dx."""
    s = _symbols(space, None, coords)
    form = ngs.BilinearForm(space)
    for term in terms:
        if (lhs := term.lhs(s, space.mesh)) is not None:
            form += lhs
        if (rhs := term.rhs(s, space.mesh)) is not None:
            form += (-1.0) * rhs
    return form


@dataclass(frozen=True)
class FixedPointForms:
    """The matrix of one Picard iteration (3.2) split as ``iterate`` (coefficients at the
    iterate: reassembled every iteration) + ``constant`` (fixed during a step), and the
    right-hand side ``rhs``."""

    iterate: ngs.BilinearForm
    constant: ngs.BilinearForm
    rhs: ngs.LinearForm
    rhs_reads_iterate: bool = False     # assembled at every iteration (a moving wall)


def fixed_point_forms(space: ngs.FESpace, terms: Sequence[Term],
                      iterate: ngs.GridFunction,
                      coords: Coordinates = PLANE) -> FixedPointForms:
    """The same terms with coefficients frozen at ``iterate``: the matrix and right-hand
    side of one Picard iteration (3.2)."""
    s = _symbols(space, iterate, coords)
    a, a0, f = ngs.BilinearForm(space), ngs.BilinearForm(space), ngs.LinearForm(space)
    for term in terms:
        if (lhs := term.lhs(s, space.mesh)) is not None:
            if getattr(term, "step_constant", False):
                a0 += lhs
            elif getattr(term, "compiled", True):
                a += lhs.Compile()   # the same matrix, ~12 % faster to assemble
            else:
                a += lhs
        if (rhs := term.rhs(s, space.mesh)) is not None:
            f += rhs
    reads = any(getattr(term, "rhs_reads_iterate", False) for term in terms)
    return FixedPointForms(iterate=a, constant=a0, rhs=f, rhs_reads_iterate=reads)
