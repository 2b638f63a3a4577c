"""The discrete flow state on one mesh and its implicit-Euler step (paper section 3.1)."""

from __future__ import annotations

from collections.abc import Sequence

import ngsolve as ngs

from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.forms import FrictionWall, build_momentum_forms, frobenius, strain_rate
from granflow.fem.nonlinear import IterationReport, PicardIteration
from granflow.fem.spaces import taylor_hood, vector_p2
from granflow.physics import DruckerPrager


class FlowSolver:
    """Velocity/pressure at t^n and t^{n+1}, the mesh velocity, and the iteration (3.2).

    All fields live on ``mesh``; moving its vertices moves them with it, which is how the
    previous velocity is carried by the nodes (u^n o A^{-1}) without interpolation.
    """

    def __init__(self, mesh: ngs.Mesh, *, rheology: DruckerPrager, density: float,
                 body_force: tuple[float, float], periodic: bool = False,
                 dirichlet: str = "", walls: Sequence[FrictionWall] = (),
                 penalty: float = 0.0) -> None:
        self.mesh = mesh
        self.rheology = rheology
        self.density = density
        self.space = taylor_hood(mesh, periodic=periodic, dirichlet=dirichlet)
        self.solution = ngs.GridFunction(self.space)    # (u^{n+1,k}, p^{n+1,k})
        self.previous = ngs.GridFunction(self.space)    # (u^n, p^n)
        self.mesh_velocity = ngs.GridFunction(vector_p2(mesh))
        self.dt = ngs.Parameter(1.0)
        self.forms = build_momentum_forms(
            self.space, self.solution, self.previous, self.mesh_velocity, rheology, density,
            body_force, self.dt, walls, penalty)
        self.picard = PicardIteration(self.forms.a, self.forms.f, self.solution,
                                      self.space.FreeDofs())

    @property
    def velocity(self) -> ngs.CoefficientFunction:
        return self.previous.components[0]

    @property
    def pressure(self) -> ngs.CoefficientFunction:
        return self.previous.components[1]

    def set_state(self, velocity: ngs.CoefficientFunction,
                  pressure: ngs.CoefficientFunction) -> None:
        """Initial condition; the pressure is also the first iterate of the first step."""
        self.previous.components[0].Set(velocity)
        self.previous.components[1].Set(pressure)
        self.solution.vec.data = self.previous.vec

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        """(u^{n+1}, p^{n+1}) on the already-moved mesh, starting from (u^n, p^n)."""
        self.dt.Set(dt)
        self.solution.vec.data = self.previous.vec
        return self.picard.solve(tol, max_iterations, velocity_floor)

    def accept(self) -> None:
        self.previous.vec.data = self.solution.vec

    def reject(self) -> None:
        self.solution.vec.data = self.previous.vec

    # --- read-only measures of the accepted state -------------------------------------
    def volume(self) -> float:
        return ngs.Integrate(ngs.CF(1.0), self.mesh)

    def kinetic_energy(self) -> float:
        u = self.velocity
        return 0.5 * self.density * ngs.Integrate(u * u, self.mesh)

    def strain_rate_norm(self) -> ngs.CoefficientFunction:
        return frobenius(strain_rate(self.velocity))

    def effective_viscosity(self) -> ngs.CoefficientFunction:
        return self.rheology.effective_viscosity(self.strain_rate_norm(), self.pressure,
                                                 NGSOLVE_OPS)
