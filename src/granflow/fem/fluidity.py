"""The granular fluidity g on the moving mesh (``physics/nonlocal_fluidity.py``): continuous
P1, carried by the nodes like the velocity of (3.2a), and its equation

    t0 (g - g^n o A^-1) / dt + t0 (u - w) . grad g - A^2 d^2 lap g + (mu_s + b I) g = gamma_dot

(implicit Euler along the mesh trajectories, the ALE convection with the mesh velocity w of
the step as in (3.2a)), with gamma_dot = sqrt(2) |Du| and I of the flow (u, p) it is solved
with. Weak form with the section's measure (r-weighted in r-z, where the Laplacian of an
axisymmetric field is (1/r) d_r(r d_r g) + d_zz g): zero flux wherever no condition is set
(the free surface, walls), g = 0 on the ``dirichlet`` boundaries (a rough base). For a given
flow the problem is linear and coercive; the coupling to the momentum is through the flow it
reads (``FluidityCoupling``: once per accepted step, or at every iteration).

Two materials (a column over a layer of its own) blend the coefficients with the
per-triangle share of layer material, as their laws are blended (``physics/regions.py``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np

from granflow.fem.coupling import Carriers, Coupling, Flow, Site
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.linalg import ReusableLU
from granflow.fem.measure import PLANE, Coordinates
from granflow.fem.sampling import cell_means, vertex_samples
from granflow.physics.nonlocal_fluidity import NonlocalFluidity
from granflow.physics.regions import blend
from granflow.state.spec import Share, array, assign, may_lack

# The reaction, time and source terms on 6 interior points (order 4). I = gamma_dot d /
# sqrt(P / rho_s) is singular where P -> 0: NGSolve's order-2 rule, which it picks for these
# terms, has its points on the edges' midpoints, where it reads P = 0 on the free surface
# and a sink 3,000 times mu_s at the surface's nodes (a g = 0 condition in effect there,
# which doubles the stopping height). P in the weak form's integrand behaves like
# depth^(-1/2): integrable, and integrated without its endpoint.
RULES = {ngs.TRIG: ngs.IntegrationRule(ngs.TRIG, 4)}


def _coefficient(laws: tuple[NonlocalFluidity, ...], fraction: Any, value: Any) -> Any:
    """``value(law)`` of one law, or of a column's and a layer's blended by ``fraction``."""
    if len(laws) == 1:
        return value(laws[0])
    return blend(value(laws[0]), value(laws[1]), fraction)


class FluidityField:
    """g^n (``previous``, the accepted state) and g (``current``, what the laws read)."""

    def __init__(self, mesh: ngs.Mesh, *, laws: tuple[NonlocalFluidity, ...],
                 fraction: Any = None, coords: Coordinates = PLANE, periodic: bool = False,
                 dirichlet: str = "", solver: str = "umfpack") -> None:
        self.mesh, self.laws, self.fraction, self.coords = mesh, laws, fraction, coords
        space = ngs.H1(mesh, order=1, dirichlet=dirichlet)
        self.space = ngs.Periodic(space) if periodic else space
        self.previous = ngs.GridFunction(self.space)
        self.current = ngs.GridFunction(self.space)
        self.dt = ngs.Parameter(1.0)
        self._form: ngs.BilinearForm | None = None
        self._rhs: ngs.LinearForm | None = None
        self._lu: ReusableLU | None = None
        self._solver = solver
        self._work = self.current.vec.CreateVector()
        self.solves = 0

    def bind(self, velocity: ngs.CoefficientFunction, pressure: ngs.CoefficientFunction,
             mesh_velocity: ngs.CoefficientFunction,
             source: ngs.CoefficientFunction | None = None) -> None:
        """The flow (u, p) and the mesh velocity w the equation reads (live fields: each
        ``solve`` assembles with their values at that moment); ``source`` is added to its
        right-hand side (a manufactured solution's, for verification)."""
        g, v = self.space.TnT()
        laws, frac, c = self.laws, self.fraction, self.coords
        rate = math.sqrt(2.0) * ngs.sqrt(c.strain_rate_sq(velocity))       # gamma_dot
        t0 = _coefficient(laws, frac, lambda law: law.time_scale(pressure, NGSOLVE_OPS))
        sink = _coefficient(laws, frac, lambda law: law.mu_s + law.b * law.inertial_number(
            rate, pressure, NGSOLVE_OPS))
        diffusivity = _coefficient(laws, frac, lambda law: law.diffusivity)
        a = ngs.BilinearForm(self.space)
        a += c.dx((t0 / self.dt + sink) * g * v, intrules=RULES)
        a += c.dx(t0 * (ngs.grad(g) * (velocity - mesh_velocity)) * v)
        if any(law.amplitude > 0 for law in laws):
            a += c.dx(diffusivity * ngs.grad(g) * ngs.grad(v))
        f = ngs.LinearForm(self.space)
        f += c.dx((t0 / self.dt * self.previous + rate) * v, intrules=RULES)
        if source is not None:
            f += c.dx(source * v)
        self._form, self._rhs = a, f
        self._lu = ReusableLU(a, self.space.FreeDofs(), self._solver)

    def solve(self, dt: float) -> float:
        """g at the end of a step of length dt from g^n and the bound flow; returns the
        relative L2 change of ``current`` (for a coupled iteration's convergence test)."""
        assert self._form is not None and self._rhs is not None and self._lu is not None
        self.dt.Set(dt)
        self._form.Assemble()
        self._rhs.Assemble()
        self._lu.update()
        self._work.data = self.current.vec
        self._lu.solve(self._rhs.vec, self.current.vec)
        self.solves += 1
        self._work.data -= self.current.vec
        change = ngs.Norm(self._work)
        norm = ngs.Norm(self.current.vec)
        return change / norm if norm > 0 else (0.0 if change == 0 else math.inf)

    def accept(self) -> None:
        self.previous.vec.data = self.current.vec

    def reject(self) -> None:
        self.current.vec.data = self.previous.vec

    def set(self, values: Any) -> None:
        """g^n = g = ``values`` (a coefficient function, or vertex values)."""
        if isinstance(values, ngs.CoefficientFunction):
            self.previous.Set(values)
        else:
            assign(self.previous.vec.FV().NumPy(), values, "the fluidity's values")
        self.reject()

    def reset_factorisation(self) -> None:
        if self._lu is not None:
            self._lu.reset()

    # --- measures of the accepted state ------------------------------------------------
    def cell_means(self) -> np.ndarray:
        """The mean of the accepted g over each triangle."""
        return cell_means(self.mesh, self.previous)[0]

    def vertex_values(self) -> np.ndarray:
        """The accepted g at every vertex (periodic copies included)."""
        return vertex_samples(self.mesh, self.previous)


@dataclass(frozen=True)
class FluiditySpec:
    """The fluidity of a run's nonlocal laws (one, or a column's and its layer's, blended
    with the share of layer material the couplings before it hand the law): g = 0 on the
    boundaries ``dirichlet``, solved once per accepted step (``iterated`` False: the
    momentum of a step reads g^n) or with every iterate; ``initial``: g at t = 0 (a
    coefficient function; None: 0)."""

    laws: tuple[NonlocalFluidity, ...]
    dirichlet: str = ""
    iterated: bool = False
    initial: Any = None

    def build(self, site: Site, fields: Mapping[str, Any]) -> FluidityCoupling:
        field = FluidityField(site.mesh, laws=self.laws, fraction=fields.get("share"),
                              coords=site.coordinates, periodic=site.periodic,
                              dirichlet=self.dirichlet, solver=site.linear_solver)
        if self.initial is not None:
            field.set(self.initial)
        return (IteratedFluidity if self.iterated else FluidityCoupling)(field)


class FluidityCoupling(Coupling):
    """The fluidity beside the flow: the nonlocal law reads g (``current``); g^{n+1} is
    solved with the accepted step's flow, kept in the checkpoint and carried through a
    remesh at the vertices."""

    name = "fluidity"
    share_of_checkpoint: Share = {"fluidity": may_lack(array("fluidity dofs"))}

    def __init__(self, field: FluidityField) -> None:
        self.field = field

    def law_fields(self) -> Mapping[str, Any]:
        return {"fluidity": self.field.current}

    def bind(self, flow: Flow) -> None:
        u, p = flow.solution.components
        self.field.bind(u, p, flow.mesh_velocity)

    def accept(self, dt: float) -> None:
        self.field.solve(dt)             # g^{n+1} with the step's flow
        self.field.accept()

    def reject(self) -> None:
        self.field.reject()

    def share(self) -> Share:
        return self.share_of_checkpoint      # restore says if it is missing

    def save(self) -> dict[str, object]:
        return {"fluidity": self.field.previous.vec.FV().NumPy().copy()}

    def restore(self, state: Mapping[str, object]) -> None:
        if "fluidity" not in state:
            raise ValueError("this checkpoint was written without a nonlocal fluidity; "
                             "run the case again from the start")
        self.field.set(state["fluidity"])

    def inherit(self, old: Coupling, carry: Carriers) -> None:
        assert isinstance(old, FluidityCoupling)
        carry.vertices(old.field.previous, self.field.previous)
        self.field.reject()

    def reset_factorisation(self) -> None:
        self.field.reset_factorisation()


class IteratedFluidity(FluidityCoupling):
    """The fluidity solved with every iterate of the nonlinear solve, its relative change
    joining the convergence test (``numerics.fluidity_coupling = "iterated"``)."""

    iterates = True
    _dt = 0.0

    def start_step(self, dt: float) -> None:
        self._dt = dt

    def iterate(self) -> float:
        return self.field.solve(self._dt)

    def accept(self, dt: float) -> None:
        self.field.accept()
