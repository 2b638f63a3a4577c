"""What a step attempt can report to the loop: typed outcomes, never matched by text.

The loop (``simulation.py``) is written against protocols; the finite-element solver
(``fem/nonlinear.py``) and the mesh motion (``ale/mesh_motion.py``) return these values.
They live here, with no finite-element import, so that the loop can be imported and
tested without NGSolve.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum


class Failure(Enum):
    """Why a nonlinear solve did not deliver a solution."""

    NOT_CONVERGED = "the nonlinear iteration did not converge"
    NON_FINITE = "the nonlinear iteration produced non-finite values"


@dataclass(frozen=True)
class IterationReport:
    """Outcome of one nonlinear solve.

    ``iterations`` counts nonlinear iterations (one linearisation and factorisation each);
    ``linear_solves`` counts every solve with a factorised matrix, including the
    back-substitutions of Newton's damping test.
    """

    converged: bool
    iterations: int
    relative_change: float
    finite: bool = True
    linear_solves: int = -1
    newton_iterations: int = 0
    picard_iterations: int = 0
    fallbacks: int = 0

    def __post_init__(self) -> None:
        if self.linear_solves < 0:
            object.__setattr__(self, "linear_solves", self.iterations)

    @property
    def failure(self) -> Failure | None:
        if not self.finite:
            return Failure.NON_FINITE
        return None if self.converged else Failure.NOT_CONVERGED


class MeshingFailed(RuntimeError):
    """A remesh could not mesh the moved domain (a boundary the mesher refuses, a polygon
    too degenerate to read): the loop goes on with the mesh it has or a smaller step. Any
    other error from a remesh is a defect and ends the run (``simulation.py``)."""


class MoveFailure(Enum):
    """Why a mesh move was refused; the first two can be cured by remeshing."""

    INVERTED = "inverted triangle(s) after the mesh move"
    SELF_INTERSECTS = "the boundary polygon self-intersects (the surface folded through)"
    CROSSED_WALL = "a boundary node crossed the bed or the wall"

    @property
    def remeshable(self) -> bool:
        return self in (MoveFailure.INVERTED, MoveFailure.SELF_INTERSECTS)


@dataclass
class RunResult:
    """Why and where the loop stopped, and what it cost."""

    status: str                      # completed | stopped | interrupted | failed
    message: str
    t_final: float
    steps: int
    rejected_steps: int
    nonlinear_iterations: int
    linear_solves: int
    wall_time_s: float
    rejections: dict[str, int] = field(default_factory=dict)
    skipped_remeshes: int = 0        # quality remeshes that failed: the run went on without
    history_restarts: int = 0        # steps begun afresh after a jump of the forcing
    remeshed_moves: int = 0          # moves that would tangle, remeshed before the step
    remesh_failures: dict[str, int] = field(default_factory=dict)  # error type -> count
