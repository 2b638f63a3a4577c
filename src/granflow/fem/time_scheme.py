"""Time schemes of the momentum equation: implicit Euler (the paper's (3.2)) and the
variable-step BDF2, siblings behind one interface.

A scheme owns the velocity-pressure history carried by the moving nodes (u^n, u^{n-1} and,
for BDF2, u^{n-2}: on an ALE mesh the time derivative is taken along the mesh
trajectories, node by node), the inertia term of the step, the first iterate predicted
from the history, and the estimate of the step's local error that the step policy
(``simulation/timestep.py``) judges. Every other term of (3.2) is the same in both.

BDF2 with steps h = t^{n+1} - t^n and h1 = t^n - t^{n-1}, omega = h / h1:

    du/dt ~ (a0 u^{n+1} - a1 u^n + a2 u^{n-1}) / h,
    a0 = (1 + 2 omega) / (1 + omega),  a1 = 1 + omega,  a2 = omega^2 / (1 + omega),

second order for any step ratio, zero-stable while omega < 1 + sqrt(2) (the step policy
grows steps by at most 2). The local error is estimated by Milne's device: the difference
between the step and the polynomial predictor through the history, scaled by the ratio of
the error the step adds to the predictor's interpolation error for the actual step sizes
(``milne_factor``). Implicit Euler keeps the factor dt / (2 dt + dt_prev) that its
verified results were obtained with: 2/3 of ``milne_factor(1, ...)`` at constant steps.
"""

from __future__ import annotations

import math
from typing import ClassVar

import ngsolve as ngs

from granflow.fem.forms import BackwardDifferenceInertia, Inertia, Term
from granflow.state.spec import TIME, Share, array, assign, may_lack

SHORT_STEP = 0.25  # a step shorter than this x the history's span does not replace it
SCHEMES = ("implicit-euler", "bdf2")


def bdf2_coefficients(h: float, h1: float) -> tuple[float, float, float]:
    """(a0, a1, a2) of the variable-step BDF2 formula for steps h (new) and h1 (last)."""
    omega = h / h1
    return (1 + 2 * omega) / (1 + omega), 1 + omega, omega**2 / (1 + omega)


def milne_factor(order: int, h: float, spans: tuple[float, ...]) -> float:
    """The share of the difference between a step and the predictor through the last
    ``order + 1`` states that is the error the step adds (Milne's device).

    The computed history carries the global error, smooth in time, which the predictor
    extrapolates; their difference is therefore the predictor's interpolation error
    prod(t^{n+1} - t_j) / (order+1)! y^(order+1). Each step adds to the global error the
    scheme's residual on the exact solution, -h times its truncation error on the monomial
    t^(order+1) / (order+1)! (t = 0 at t^{n+1}). ``spans`` are the gaps between the
    history states, newest first. Constant steps: 1/2 (implicit Euler), 1/3 (BDF2).
    """
    times = [-h]
    for span in spans[:order]:
        times.append(times[-1] - span)
    fact = math.factorial(order + 1)
    predictor = math.prod(-t for t in times) / fact
    if order == 1:
        truncation = -(times[0] ** 2) / fact / h
    else:
        _, a1, a2 = bdf2_coefficients(h, spans[0])
        truncation = (-a1 * times[0] ** 3 + a2 * times[1] ** 3) / fact / h
    return -h * truncation / predictor


class TimeScheme:
    """History, inertia term, predictor and local error of one scheme (base class).

    ``previous`` holds (u^n, p^n), ``before_previous`` (u^{n-1}, p^{n-1}) at
    ``dt_previous`` before it; a step shorter than SHORT_STEP x dt_previous keeps the
    older state as the baseline (a difference over a sliver of time would amplify noise).
    """

    name: ClassVar[str]
    order: ClassVar[int]
    depth: ClassVar[int]      # history states kept (besides the newest)
    share: ClassVar[Share] = {"previous": array("dofs"), "before_previous": array("dofs"),
                              "dt_previous": TIME}      # of a checkpoint (``save``)

    def __init__(self, space: ngs.FESpace, density: float | ngs.CoefficientFunction) -> None:
        self.density = density
        self.dt = ngs.Parameter(1.0)
        self.previous = ngs.GridFunction(space)         # (u^n, p^n)
        self.before_previous = ngs.GridFunction(space)  # (u^{n-1}, p^{n-1})
        self.dt_previous = 0.0                          # t^n - t^{n-1}; 0 = no history

    # --- the step --------------------------------------------------------------------
    def inertia(self) -> Term:
        """The inertia term of (3.2a) for this scheme."""
        raise NotImplementedError

    def begin_step(self, dt: float) -> None:
        """Set the step's coefficients for a step of size dt."""
        self.dt.Set(dt)

    def predict(self, dt: float, out: ngs.GridFunction) -> None:
        """Linear extrapolation x^n + dt (x^n - x^{n-1}) / dt_{n-1} (x^n without history)."""
        out.vec.data = self.previous.vec
        if self.dt_previous > 0:
            ratio = dt / self.dt_previous
            out.vec.data += ratio * self.previous.vec
            out.vec.data -= ratio * self.before_previous.vec

    def error_predictor(self, dt: float, out: ngs.GridFunction) -> float | None:
        """The predictor of the error estimate into ``out`` and its Milne factor (None
        when the history is too short for an estimate)."""
        if self.dt_previous <= 0:
            return None
        self.predict(dt, out)
        return dt / (2 * dt + self.dt_previous)

    # --- history ---------------------------------------------------------------------
    def states(self) -> list[ngs.GridFunction]:
        """The history fields a remesh must carry over (newest first)."""
        return [self.previous, self.before_previous]

    def set_initial(self) -> None:
        """``previous`` was just set: no history yet."""
        self.before_previous.vec.data = self.previous.vec
        self.dt_previous = 0.0

    def accept(self, solution: ngs.GridFunction, dt: float | None) -> None:
        """(u^{n+1}, p^{n+1}) becomes u^n; ``dt`` the step just taken (None: no history)."""
        if dt is None:
            self.dt_previous = 0.0
        elif self.dt_previous > 0 and dt < SHORT_STEP * self.dt_previous:
            self.dt_previous += dt                   # keep u^{n-1}: a longer baseline
        else:
            self._shift(dt)
        self.previous.vec.data = solution.vec

    def _shift(self, dt: float) -> None:
        self.before_previous.vec.data = self.previous.vec
        self.dt_previous = dt

    def save(self) -> dict[str, object]:
        return {"previous": self.previous.vec.FV().NumPy().copy(),
                "before_previous": self.before_previous.vec.FV().NumPy().copy(),
                "dt_previous": self.dt_previous}

    def restore(self, state: dict[str, object]) -> None:
        assign(self.previous.vec.FV().NumPy(), state["previous"], "the saved u^n")
        assign(self.before_previous.vec.FV().NumPy(), state["before_previous"],
               "the saved u^{n-1}")
        self.dt_previous = float(state["dt_previous"])  # type: ignore[arg-type]

    def inherit(self, other: TimeScheme, carry: object) -> None:
        """Take ``other``'s history on a new mesh; ``carry(old, new)`` transfers a field."""
        carry(other.previous, self.previous)                         # type: ignore[operator]
        if other.dt_previous > 0:
            carry(other.before_previous, self.before_previous)       # type: ignore[operator]
            self.dt_previous = other.dt_previous


class ImplicitEuler(TimeScheme):
    """(u^{n+1} - u^n o A^{-1}) / dt: the paper's scheme (3.2), first order."""

    name = "implicit-euler"
    order = 1
    depth = 1

    def inertia(self) -> Term:
        return Inertia(self.density, self.dt, self.previous.components[0])


class BDF2(TimeScheme):
    """The variable-step second-order backward difference formula (module docstring).

    The first step (no history) is implicit Euler; the error estimate needs two history
    states and falls back to implicit Euler's (larger, so safe) with one.
    """

    name = "bdf2"
    order = 2
    depth = 2
    share = {**TimeScheme.share, "oldest": may_lack(array("dofs")),   # an implicit-Euler
             "dt_older": may_lack(TIME)}                             # run's has neither

    def __init__(self, space: ngs.FESpace, density: float | ngs.CoefficientFunction) -> None:
        super().__init__(space, density)
        self.oldest = ngs.GridFunction(space)       # (u^{n-2}, p^{n-2})
        self.dt_older = 0.0                         # t^{n-1} - t^{n-2}; 0 = none
        self.a0 = ngs.Parameter(1.0)
        self.history = ngs.GridFunction(space.components[0])  # a1 u^n - a2 u^{n-1}

    def inertia(self) -> Term:
        return BackwardDifferenceInertia(self.density, self.dt, self.a0, self.history)

    def begin_step(self, dt: float) -> None:
        super().begin_step(dt)
        u_n = self.previous.components[0].vec
        if self.dt_previous <= 0:
            self.a0.Set(1.0)
            self.history.vec.data = u_n
            return
        a0, a1, a2 = bdf2_coefficients(dt, self.dt_previous)
        self.a0.Set(a0)
        self.history.vec.data = a1 * u_n
        self.history.vec.data -= a2 * self.before_previous.components[0].vec

    def error_predictor(self, dt: float, out: ngs.GridFunction) -> float | None:
        """The quadratic predictor through the three last states and its Milne factor (the
        first iterate stays the linear ``predict``: from the quadratic one, whose weights
        3, -3, 1 amplify the iteration's own error in the history, the default collapse
        took twice the iterations per step)."""
        if self.dt_older <= 0 or self.dt_previous <= 0:
            return super().error_predictor(dt, out)
        t1, t2 = -self.dt_previous, -self.dt_previous - self.dt_older   # t^n = 0
        w0 = (dt - t1) * (dt - t2) / (t1 * t2)
        w1 = dt * (dt - t2) / (t1 * (t1 - t2))
        w2 = dt * (dt - t1) / (t2 * (t2 - t1))
        out.vec.data = w0 * self.previous.vec
        out.vec.data += w1 * self.before_previous.vec
        out.vec.data += w2 * self.oldest.vec
        return milne_factor(2, dt, (self.dt_previous, self.dt_older))

    def states(self) -> list[ngs.GridFunction]:
        return [*super().states(), self.oldest]

    def set_initial(self) -> None:
        super().set_initial()
        self.oldest.vec.data = self.previous.vec
        self.dt_older = 0.0

    def accept(self, solution: ngs.GridFunction, dt: float | None) -> None:
        if dt is None:
            self.dt_older = 0.0
        super().accept(solution, dt)

    def _shift(self, dt: float) -> None:
        if self.dt_previous > 0:
            self.oldest.vec.data = self.before_previous.vec
            self.dt_older = self.dt_previous
        super()._shift(dt)

    def save(self) -> dict[str, object]:
        return super().save() | {"oldest": self.oldest.vec.FV().NumPy().copy(),
                                 "dt_older": self.dt_older}

    def restore(self, state: dict[str, object]) -> None:
        super().restore(state)
        if "oldest" in state:
            assign(self.oldest.vec.FV().NumPy(), state["oldest"], "the saved u^{n-2}")
            self.dt_older = float(state["dt_older"])  # type: ignore[arg-type]
        else:   # a checkpoint of an implicit-Euler run: start the third state afresh
            self.dt_older = 0.0

    def inherit(self, other: TimeScheme, carry: object) -> None:
        super().inherit(other, carry)
        if isinstance(other, BDF2) and other.dt_older > 0 and other.dt_previous > 0:
            carry(other.oldest, self.oldest)                         # type: ignore[operator]
            self.dt_older = other.dt_older


def time_scheme(name: str, space: ngs.FESpace,
                density: float | ngs.CoefficientFunction) -> TimeScheme:
    """The scheme of ``time.scheme``."""
    if name == "bdf2":
        return BDF2(space, density)
    if name == "implicit-euler":
        return ImplicitEuler(space, density)
    raise ValueError(f"time.scheme must be one of {SCHEMES}, not {name!r}")
