"""The discrete flow state on one mesh and its time step (paper section 3.1): the terms of
(3.2), the time scheme's history and inertia (``fem/time_scheme.py``), the nonlinear solve,
and the fields coupled to the flow (``fem/coupling.py``), stepped with it. Built from
frozen parts by ``fem/flow_factory.py: build_flow``."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TypeVar

import ngsolve as ngs
import numpy as np

from granflow.fem.coupling import Carriers, Coupling, Iteration
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.flow_spec import Density, SolverChoice
from granflow.fem.forms import Term, frobenius
from granflow.fem.measure import Coordinates
from granflow.fem.nonlinear import NonlinearSolver
from granflow.fem.time_scheme import TimeScheme
from granflow.physics import Rheology
from granflow.simulation.outcomes import IterationReport
from granflow.state.spec import FLAG, Share, may_lack

C = TypeVar("C", bound=Coupling)


@dataclass(frozen=True)
class FlowParts:
    """What ``build_flow`` made on one mesh for the solver to hold."""

    mesh: ngs.Mesh
    space: ngs.FESpace
    solution: ngs.GridFunction          # (u^{n+1,k}, p^{n+1,k})
    scheme: TimeScheme
    mesh_velocity: ngs.GridFunction     # w
    surface_tension: ngs.GridFunction   # gamma of (2.11)/(3.8) at the vertices
    rheology: Rheology
    density: Density
    coordinates: Coordinates
    terms: Sequence[Term]
    choice: SolverChoice
    couplings: tuple[Coupling, ...]


class FlowSolver:
    """Velocity/pressure at t^n and t^{n+1}, the mesh velocity, and the iteration (3.2).

    All fields live on ``mesh``; moving its vertices moves them with it, which is how the
    previous velocity is carried by the nodes (u^n o A^{-1}) without interpolation.
    ``couplings``: the fields coupled to the flow, stepped, saved and carried with it.
    """

    def __init__(self, parts: FlowParts, nonlinear: NonlinearSolver) -> None:
        self.mesh, self.space, self.solution = parts.mesh, parts.space, parts.solution
        self.scheme: TimeScheme = parts.scheme
        self.previous = self.scheme.previous                # (u^n, p^n)
        self.before_previous = self.scheme.before_previous  # (u^{n-1}, p^{n-1})
        self.dt = self.scheme.dt
        self.mesh_velocity, self.surface_tension = parts.mesh_velocity, parts.surface_tension
        self.rheology, self.density = parts.rheology, parts.density
        self.coordinates, self.terms = parts.coordinates, parts.terms
        self.linearization = parts.choice.linearization
        self.initial_guess = parts.choice.initial_guess
        self.nonlinear = nonlinear
        self.couplings = parts.couplings
        self.extrapolation_won = True           # "auto": which guess predicted the last step
        self._history_kept: dict[str, object] | None = None   # set aside by a restart
        for coupling in self.couplings:
            coupling.bind(self)
        # a field solved with every iterate: its relative change joins the convergence test
        self._iterating = tuple(c for c in self.couplings if c.iterates)
        self.nonlinear.coupled = self._coupled_change if self._iterating else None
        default: Iteration = {"newton": nonlinear.solve_newton,
                              "hybrid": nonlinear.solve_hybrid}.get(self.linearization,
                                                                     nonlinear.solve_picard)
        self.iteration = default
        for coupling in self.couplings:
            self.iteration = coupling.iteration(self.iteration)
        # Newton and the hybrid start from the extrapolation unless a coupling iterates
        # the step its own way
        self._own_iteration = self.iteration is not default

    def _coupled_change(self) -> float:
        """Each iterating coupling solved with the current iterate: the largest change."""
        return max(c.iterate() for c in self._iterating)

    def coupling(self, kind: type[C]) -> C | None:
        """The coupling of this kind, or None when the run has none."""
        return next((c for c in self.couplings if isinstance(c, kind)), None)

    @property
    def dt_previous(self) -> float:
        """t^n - t^{n-1} of the history (0: none yet)."""
        return self.scheme.dt_previous

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
        self.scheme.set_initial()

    def solve_step(self, dt: float, tol: float, max_iterations: int,
                   velocity_floor: float = 0.0) -> IterationReport:
        """(u^{n+1}, p^{n+1}) on the already-moved mesh, from the first iterate of
        ``first_iterate_extrapolated``."""
        self.scheme.begin_step(dt)
        if self.first_iterate_extrapolated():
            self.predict(dt, self.solution)
        else:
            self.solution.vec.data = self.previous.vec
        for coupling in self.couplings:
            coupling.start_step(dt)
        return self.iteration(tol, max_iterations, velocity_floor)

    def first_iterate_extrapolated(self) -> bool:
        """Whether the step starts from the linear extrapolation of the last two steps
        (``predict``) rather than from (u^n, p^n) as in (3.2).

        "previous": (u^n, p^n) for Picard; Newton and the hybrid always extrapolate.
        "extrapolated": always extrapolate. "auto": whichever of the two predicted the last
        accepted step better (``accept``). Near rest the step-to-step change is below the
        nonlinear solver's own error, which the extrapolation doubles: a 10 deg slope's
        deposit then needs 16-122 Picard iterations per step from the extrapolation and
        1-2 from (u^n, p^n), both ending 1e-6 m/s from the fixed point.
        """
        if self.initial_guess == "auto":
            return self.extrapolation_won
        return self.initial_guess == "extrapolated" or (self.linearization in ("newton", "hybrid")
                                                        and not self._own_iteration)

    def predict(self, dt: float, out: ngs.GridFunction) -> None:
        """The time scheme's extrapolation of the history to t^n + dt."""
        self.scheme.predict(dt, out)

    def local_error(self, dt: float) -> tuple[float, float] | None:
        """(estimated local velocity error of the step, velocity scale), RMS over the domain.

        Milne's device (``fem/time_scheme.py``): the step's difference from the scheme's
        polynomial predictor through the history, times the share of it that is the
        scheme's local error. For implicit Euler, whose local error is dt^2/2 u'', the
        linear extrapolation of the last two steps misses by dt (2 dt + dt_prev) / 2 u'', so
        error = dt / (2 dt + dt_prev) ||u^{n+1} - u_pred||. None before two steps exist.
        Velocities are compared node by node: they are carried by the moving mesh, so this
        is the error along the mesh trajectories, as the scheme (3.2) steps.
        """
        guess = self.nonlinear.scratch
        factor = self.scheme.error_predictor(dt, guess)
        if factor is None:
            return None
        root_area = math.sqrt(ngs.Integrate(ngs.CF(1.0), self.mesh))   # RMS of the L2 norm
        guess.vec.data -= self.solution.vec
        difference = self.nonlinear.velocity_l2(guess.vec)
        speed = self.nonlinear.velocity_l2(self.solution.vec)
        return factor * difference / root_area, speed / root_area

    def _miss(self, dt: float, extrapolated: bool) -> float:
        """||u^{n+1} - guess|| (velocity, L2) for the extrapolated guess or for u^n."""
        guess = self.nonlinear.scratch
        if extrapolated:
            self.predict(dt, guess)
        else:
            guess.vec.data = self.previous.vec
        guess.vec.data -= self.solution.vec
        return self.nonlinear.velocity_l2(guess.vec)

    def accept(self, dt: float | None = None) -> None:
        """(u^{n+1}, p^{n+1}) becomes the state; ``dt`` the step just taken.

        The history (u^{n-1}, dt_{n-1}) that extrapolations read spans at least a quarter
        of the last full step: after a step cut short (to land a node or hit an output
        time) it keeps the older state, since a difference over a sliver of time would
        amplify its noise in the extrapolation by dt / dt_{n-1}.
        """
        if self.initial_guess == "auto" and dt is not None and self.dt_previous > 0:
            self.extrapolation_won = (self._miss(dt, extrapolated=True)
                                      <= self._miss(dt, extrapolated=False))
        step = self.dt.Get()     # the step just solved (``dt`` may be None)
        for coupling in self.couplings:
            coupling.accept(step)
        self.scheme.accept(self.solution, dt)
        self._history_kept = None

    def reject(self) -> None:
        """Back to the state at the start of the rejected step: the history a restart set
        aside, and the couplings' states (a failed iteration's are no start for the
        retry)."""
        if self._history_kept is not None:       # the step had restarted the history
            self.scheme.restore(self._history_kept)
            self._history_kept = None
        self.solution.vec.data = self.previous.vec
        for coupling in self.couplings:
            coupling.reject()

    def restart_history(self) -> None:
        """Forget the states before (u^n, p^n) for this step: the forcing jumped, so it is a
        first step (implicit Euler from (u^n, p^n), no local error estimate) as after
        ``set_state``. ``reject`` gives the history back (a retry may not jump)."""
        if self._history_kept is None:
            self._history_kept = self.scheme.save()
        self.scheme.set_initial()

    def save_history(self) -> dict[str, object]:
        """(u^n, p^n), (u^{n-1}, p^{n-1}) and dt_{n-1}: what the next step reads, and each
        coupling's share (the augmented Lagrangian's d and lambda, a fluidity)."""
        state: dict[str, object] = self.scheme.save() | {
            "extrapolation_won": self.extrapolation_won}
        for coupling in self.couplings:
            state |= coupling.save()
        return state

    def history_share(self) -> Share:
        """What the members of ``save_history`` may be (in a checkpoint)."""
        share = {**self.scheme.share, "extrapolation_won": may_lack(FLAG)}
        for coupling in self.couplings:
            share |= coupling.share()
        return share

    def restore_history(self, state: dict[str, object]) -> None:
        """Inverse of ``save_history`` on a solver built on the same mesh."""
        self.scheme.restore(state)
        self.extrapolation_won = bool(state.get("extrapolation_won", True))
        self.solution.vec.data = self.previous.vec
        for coupling in self.couplings:
            coupling.restore(state)

    def inherit(self, old: FlowSolver, carry: Carriers) -> None:
        """Continue ``old``'s run on this solver's (new) mesh after a remesh: the time
        scheme's history, the first iterate, the "auto" guess's choice and each coupling
        (``carry`` moves the fields, ``ale/transfer.py``)."""
        self.scheme.inherit(old.scheme, carry.state)
        self.solution.vec.data = self.previous.vec
        self.extrapolation_won = old.extrapolation_won
        self.nonlinear.carried_work = old.linear_work()
        before = {c.name: c for c in old.couplings}
        for coupling in self.couplings:
            if coupling.name in before:
                coupling.inherit(before[coupling.name], carry)

    def linear_work(self) -> dict[str, int]:
        """The iterative linear solves' counts over the run, for summary.json (none with
        a direct solve: ``NonlinearSolver.linear_work``)."""
        return self.nonlinear.linear_work()

    def reset_factorisations(self) -> None:
        """Forget every symbolic LU: the flow's and its couplings' (after a checkpoint, so
        that the run goes on as one resumed from it does)."""
        self.nonlinear.reset_factorisations()
        for coupling in self.couplings:
            coupling.reset_factorisation()

    def volume_excess(self, xy: np.ndarray) -> float:
        """What the free-surface fix conserves beside the section's measure, each
        coupling's (``Coupling.volume_excess``; 0 for an incompressible flow)."""
        return sum((c.volume_excess(xy) for c in self.couplings), 0.0)

    # --- read-only measures of the accepted state -------------------------------------
    def volume(self) -> float:
        """m^2 per metre of width in plane strain, m^3 in axisymmetry."""
        return self.coordinates.integrate(ngs.CF(1.0), self.mesh)

    def kinetic_energy(self) -> float:
        u = self.velocity
        if isinstance(self.density, ngs.CoefficientFunction):    # two materials
            return 0.5 * self.coordinates.integrate(self.density * u * u, self.mesh)
        return 0.5 * self.density * self.coordinates.integrate(u * u, self.mesh)

    def strain_rate_norm(self) -> ngs.CoefficientFunction:
        return frobenius(self.coordinates.strain_rate(self.velocity))

    def effective_viscosity(self) -> ngs.CoefficientFunction:
        return self.rheology.effective_viscosity(self.strain_rate_norm(), self.pressure,
                                                 NGSOLVE_OPS)
