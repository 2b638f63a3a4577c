"""The discrete flow state on one mesh and its time step (paper section 3.1): the terms of
(3.2), the time scheme's history and inertia (``fem/time_scheme.py``), the nonlinear solve."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import ngsolve as ngs

from granflow.fem.augmented_lagrangian import (
    AugmentedLagrangian,
    AugmentedStress,
    tensor_space,
)
from granflow.fem.engine import NGSOLVE_OPS
from granflow.fem.fluidity import FluidityField
from granflow.fem.forms import (
    FrictionWall,
    SurfaceTraction,
    fixed_point_forms,
    frobenius,
    momentum_terms,
    residual_form,
)
from granflow.fem.measure import PLANE, Coordinates
from granflow.fem.nonlinear import FixedPointSystem, NonlinearSolver, ResidualSystem
from granflow.fem.primal_dual import DualVariable
from granflow.fem.spaces import taylor_hood, vector_p2
from granflow.fem.time_scheme import TimeScheme, time_scheme
from granflow.physics import DruckerPrager, Rheology, SideWallFriction
from granflow.physics.composite import simple_laws
from granflow.simulation.outcomes import IterationReport
from granflow.simulation.state_spec import FLAG, Share, array, assign, may_lack, number

Carry = Callable[[ngs.GridFunction, ngs.GridFunction], None]   # (old field, new field)


Density = float | ngs.CoefficientFunction   # kg/m^3: one material, or blended (two)


def drucker_prager(law: Rheology) -> bool:
    """The Drucker-Prager law (2.13), alone, as both materials of a column over a layer, or
    with a hysteretic friction: what the primal-dual correction is built for."""
    return all(isinstance(part, DruckerPrager) for part in simple_laws(law))


class FlowSolver:
    """Velocity/pressure at t^n and t^{n+1}, the mesh velocity, and the iteration (3.2).

    All fields live on ``mesh``; moving its vertices moves them with it, which is how the
    previous velocity is carried by the nodes (u^n o A^{-1}) without interpolation.
    """

    def __init__(self, mesh: ngs.Mesh, *, rheology: Rheology, density: Density,
                 body_force: tuple[float, float], periodic: bool = False,
                 dirichlet: str = "", walls: Sequence[FrictionWall] = (),
                 penalty: float = 0.0, linearization: str = "picard",
                 linear_solver: str = "umfpack", initial_guess: str = "previous",
                 surface_tension_on: str | None = None,
                 side_walls: SideWallFriction | None = None,
                 augmentation: float | None = None, scheme: str = "implicit-euler",
                 coordinates: Coordinates = PLANE, axis: str = "",
                 anderson_depth: int = 0, fluidity: FluidityField | None = None,
                 fluidity_coupling: str = "lagged") -> None:
        self.mesh = mesh
        self.initial_guess = initial_guess
        self.linearization = linearization
        self.rheology = rheology
        self.density = density
        self.coordinates = coordinates
        self.space = taylor_hood(mesh, periodic=periodic, dirichlet=dirichlet, axis=axis)
        self.solution = ngs.GridFunction(self.space)    # (u^{n+1,k}, p^{n+1,k})
        self.scheme: TimeScheme = time_scheme(scheme, self.space, density)
        self.previous = self.scheme.previous                # (u^n, p^n)
        self.before_previous = self.scheme.before_previous  # (u^{n-1}, p^{n-1})
        self.dt = self.scheme.dt
        self.mesh_velocity = ngs.GridFunction(vector_p2(mesh))
        self.extrapolation_won = True           # "auto": which guess predicted the last step
        self._history_kept: dict[str, object] | None = None   # set aside by a restart
        # gamma of (2.11)/(3.8) at the vertices, on the boundary ``surface_tension_on``
        self.surface_tension = ngs.GridFunction(ngs.H1(mesh, order=1))
        traction = (None if surface_tension_on is None
                    else SurfaceTraction(surface_tension_on, self.surface_tension))
        stress = None
        if augmentation is not None:        # the augmented Lagrangian method, not (2.13)
            if coordinates.axisymmetric:
                raise ValueError("the augmented Lagrangian method is plane strain only")
            if not isinstance(rheology, DruckerPrager):
                raise ValueError("the augmented Lagrangian method needs the Drucker-Prager law")
            self.strain = ngs.GridFunction(tensor_space(mesh))       # d
            self.multiplier = ngs.GridFunction(tensor_space(mesh))   # lambda
            self.augmentation = ngs.Parameter(augmentation)           # r, balanced
            stress = AugmentedStress(rheology, self.augmentation, self.strain,
                                     self.multiplier)
        self.terms = momentum_terms(
            density=density, inertia=self.scheme.inertia(),
            mesh_velocity=self.mesh_velocity, rheology=rheology, body_force=body_force,
            walls=walls, penalty=penalty, surface_traction=traction, side_walls=side_walls,
            stress=stress, coords=coordinates)
        freedofs = self.space.FreeDofs()
        forms = fixed_point_forms(self.space, self.terms, self.solution, coordinates)
        dual = correction = None
        # the correction is built for the plane Drucker-Prager law; with another law (mu(I))
        # or in axisymmetry "primal-dual" is the plain iteration (3.2) (docs/parameters.md)
        if (linearization == "primal-dual" and augmentation is None
                and drucker_prager(rheology) and not coordinates.axisymmetric):
            dual = DualVariable(mesh, rheology, self.solution)
            correction = dual.forms(self.space)
        picard = FixedPointSystem(forms.iterate, forms.rhs, freedofs, linear_solver,
                                  constant=forms.constant, correction=correction,
                                  rhs_reads_iterate=forms.rhs_reads_iterate)
        self.nonlinear = NonlinearSolver(
            picard=picard,
            newton=ResidualSystem(residual_form(self.space, self.terms, coordinates), freedofs,
                                  linear_solver),
            state=self.solution, dual=dual, anderson_depth=anderson_depth)
        self.augmented = (None if augmentation is None else AugmentedLagrangian(
            rheology, self.augmentation, self.nonlinear, self.strain, self.multiplier))
        # the granular fluidity of a nonlocal law (fem/fluidity.py), solved with the flow
        # of each accepted step ("lagged") or of each iterate ("iterated")
        self.fluidity, self.fluidity_coupling = fluidity, fluidity_coupling
        if fluidity is not None:
            u, p = self.solution.components
            fluidity.bind(u, p, self.mesh_velocity)

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
        if self.augmented is not None:
            return self.augmented.solve(tol, max_iterations, velocity_floor)
        coupled = self.fluidity is not None and self.fluidity_coupling == "iterated"
        self.nonlinear.coupled = (lambda: self.fluidity.solve(dt)) if coupled else None
        if self.linearization in ("picard", "primal-dual"):
            return self.nonlinear.solve_picard(tol, max_iterations, velocity_floor)
        if self.linearization == "newton":
            return self.nonlinear.solve_newton(tol, max_iterations, velocity_floor)
        return self.nonlinear.solve_hybrid(tol, max_iterations, velocity_floor)

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
                                                        and self.augmented is None)

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
        if self.fluidity is not None:
            if self.fluidity_coupling == "lagged":   # g^{n+1} with the step's flow
                self.fluidity.solve(self.dt.Get())
            self.fluidity.accept()
        self.scheme.accept(self.solution, dt)
        self._history_kept = None
        if self.augmented is not None:
            self.augmented.remember()

    def reject(self) -> None:
        """Back to the state at the start of the rejected step: the history a restart set
        aside, and the augmented Lagrangian's d, lambda and r (a failed iteration's are no
        start for the retry)."""
        if self._history_kept is not None:       # the step had restarted the history
            self.scheme.restore(self._history_kept)
            self._history_kept = None
        self.solution.vec.data = self.previous.vec
        if self.augmented is not None:
            self.augmented.restore()
        if self.fluidity is not None:
            self.fluidity.reject()

    def restart_history(self) -> None:
        """Forget the states before (u^n, p^n) for this step: the forcing jumped, so it is a
        first step (implicit Euler from (u^n, p^n), no local error estimate) as after
        ``set_state``. ``reject`` gives the history back (a retry may not jump)."""
        if self._history_kept is None:
            self._history_kept = self.scheme.save()
        self.scheme.set_initial()

    def save_history(self) -> dict[str, object]:
        """(u^n, p^n), (u^{n-1}, p^{n-1}) and dt_{n-1}: what the next step reads (and the
        augmented Lagrangian's d and lambda, its next step's starting point)."""
        state: dict[str, object] = self.scheme.save() | {
            "extrapolation_won": self.extrapolation_won}
        if self.augmented is not None:
            state["strain"] = self.strain.vec.FV().NumPy().copy()
            state["multiplier"] = self.multiplier.vec.FV().NumPy().copy()
            state["augmentation"] = self.augmentation.Get()
        if self.fluidity is not None:
            state["fluidity"] = self.fluidity.previous.vec.FV().NumPy().copy()
        return state

    def history_share(self) -> Share:
        """What the members of ``save_history`` may be (in a checkpoint)."""
        share = {**self.scheme.share, "extrapolation_won": may_lack(FLAG)}
        if self.augmented is not None:
            share |= {"strain": array("strain dofs"), "multiplier": array("strain dofs"),
                      "augmentation": may_lack(number(0.0, above=True))}
        if self.fluidity is not None:     # restore_history says if it is missing
            share |= {"fluidity": may_lack(array("fluidity dofs"))}
        return share

    def restore_history(self, state: dict[str, object]) -> None:
        """Inverse of ``save_history`` on a solver built on the same mesh."""
        self.scheme.restore(state)
        self.extrapolation_won = bool(state.get("extrapolation_won", True))
        self.solution.vec.data = self.previous.vec
        if self.augmented is not None:
            assign(self.strain.vec.FV().NumPy(), state["strain"], "the saved strain rate d")
            assign(self.multiplier.vec.FV().NumPy(), state["multiplier"],
                   "the saved multiplier lambda")
            if "augmentation" in state:
                self.augmentation.Set(float(state["augmentation"]))  # type: ignore[arg-type]
            self.augmented.remember()
        if self.fluidity is not None:
            if "fluidity" not in state:
                raise ValueError("this checkpoint was written without a nonlocal fluidity; "
                                 "run the case again from the start")
            self.fluidity.set(state["fluidity"])

    def inherit(self, old: FlowSolver, carry: Carry, carry_tensor: Carry,
                carry_vertices: Carry | None = None) -> None:
        """Continue ``old``'s run on this solver's (new) mesh after a remesh: the time
        scheme's history, the first iterate, the "auto" guess's choice, the augmented
        Lagrangian's warm start (d, lambda, r) and a nonlocal law's fluidity.
        ``carry(old_field, new_field)`` moves a Taylor-Hood state, ``carry_tensor`` a tensor
        field, ``carry_vertices`` a continuous P1 field (``ale/transfer.py``)."""
        self.scheme.inherit(old.scheme, carry)
        self.solution.vec.data = self.previous.vec
        self.extrapolation_won = old.extrapolation_won
        if old.augmented is not None and self.augmented is not None:
            carry_tensor(old.strain, self.strain)
            carry_tensor(old.multiplier, self.multiplier)
            self.augmentation.Set(old.augmentation.Get())
            self.augmented.remember()
        if old.fluidity is not None and self.fluidity is not None:
            assert carry_vertices is not None
            carry_vertices(old.fluidity.previous, self.fluidity.previous)
            self.fluidity.reject()

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
