"""The fields coupled to the flow, behind one protocol (as Gusto's time loop takes its
advected and diffused fields as parts it walks, never as branches).

A coupling is built on the flow's mesh from a frozen spec (``CouplingSpec.build``) before
the law: it hands the law the fields it reads (``law_fields``: members of
``physics/laws.py: LawFields``, e.g. the nonlocal fluidity g, a hysteretic friction's
mobilisation, the share of layer material). Once the flow's spaces exist it may change
the forms of (3.2): replace the stress term (the augmented Lagrangian's), add terms
(``terms``: a source in the continuity row, say), add a correction to the fixed-point
matrix (the primal-dual one), replace the step's iteration (ALG2), and ``bind`` to the
flow's fields (u, p and the mesh velocity w). A field that makes the flow compressible also
says what the free-surface fix must conserve beside the section's area (``volume_excess``:
the packing fraction's mass). Through a run it is stepped with the flow:
at the start of a step, with every iterate of the nonlinear solve (``iterates``), on
acceptance and on rejection; it gives and takes its share of the checkpoint, carries
itself onto a new mesh (``inherit``) and forgets its factorisations. ``FlowSolver``
(``fem/flow.py``) holds a tuple of couplings and loops over it; nothing outside a
coupling's own module asks whether it is there. The base class does nothing at each of
these moments, so a coupling says only what it does.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

import ngsolve as ngs
import numpy as np

from granflow.fem.forms import StressTerm, Term
from granflow.fem.measure import Coordinates
from granflow.simulation.outcomes import IterationReport
from granflow.state.spec import Share

Carry = Callable[[ngs.GridFunction, ngs.GridFunction], None]   # (old field, new field)
Iteration = Callable[[float, int, float], IterationReport]      # (tol, max, velocity floor)


@dataclass(frozen=True)
class Carriers:
    """How a remesh moves fields onto the new mesh (``ale/transfer.py``): a Taylor-Hood
    state, a discontinuous tensor field, a continuous P1 field, a piecewise constant one."""

    state: Carry
    tensor: Carry
    vertices: Carry
    cells: Carry


@dataclass(frozen=True)
class Site:
    """Where a coupling is built: the flow's mesh, its coordinates, its boundary layout
    and the sparse LU the run uses."""

    mesh: ngs.Mesh
    coordinates: Coordinates
    periodic: bool
    linear_solver: str


class Flow(Protocol):
    """What a coupling reads of the flow it is bound to (``FlowSolver``)."""

    mesh: ngs.Mesh
    space: ngs.FESpace
    solution: ngs.GridFunction        # (u, p) of the step being solved
    mesh_velocity: ngs.GridFunction   # w
    coordinates: Coordinates
    rheology: Any
    nonlinear: Any                    # its ``fem/nonlinear.py: NonlinearSolver``


class Coupling:
    """A field coupled to the flow (module docstring). Subclasses override what they do;
    ``name`` pairs a coupling with its predecessor on the old mesh of a remesh."""

    name: ClassVar[str]
    iterates: ClassVar[bool] = False   # solved with every iterate of the nonlinear solve

    # --- before the forms: what it hands the law, what it changes in (3.2) ---------------
    def law_fields(self) -> Mapping[str, Any]:
        return {}

    def stress(self, stress: StressTerm, law: Any) -> StressTerm:
        """The stress term of (3.2) with this coupling (``stress`` without it)."""
        return stress

    def terms(self) -> Sequence[Term]:
        """Terms this coupling adds to every form of (3.2) (Picard's and Newton's): e.g. a
        source of the continuity row, or a density of its own in the inertia."""
        return ()

    def corrections(self, flow: Flow) -> tuple[Any, ...]:
        """A correction of the fixed-point iteration (3.2) (the dual variable of
        ``fem/primal_dual.py``, which ``fem/nonlinear.py`` steps)."""
        return ()

    def bind(self, flow: Flow) -> None:
        """The flow is built: read its fields (u, p, w) from now on."""

    def iteration(self, default: Iteration) -> Iteration:
        """The step's nonlinear iteration with this coupling (``default`` without it)."""
        return default

    # --- through a step --------------------------------------------------------------------
    def start_step(self, dt: float) -> None:
        """A step of length dt begins (the mesh has moved)."""

    def iterate(self) -> float:
        """Solved with the current iterate (``iterates``): the relative change."""
        return 0.0

    def accept(self, dt: float) -> None:
        """The step of length dt is accepted (before the flow's history moves on)."""

    def reject(self) -> None:
        """Back to the state at the start of the rejected step."""

    def volume_excess(self, xy: np.ndarray) -> float:
        """What the free-surface fix conserves beside the section's measure, with the
        vertices at ``xy`` (``ale/column_mover.py``): the measure the mass would fill at
        a reference density less the section's, or 0 (an incompressible flow: the measure
        alone)."""
        return 0.0

    # --- checkpoint, remesh, factorisations --------------------------------------------------
    def share(self) -> Share:
        """What the members of ``save`` may be (in a checkpoint)."""
        return {}

    def save(self) -> dict[str, object]:
        return {}

    def restore(self, state: Mapping[str, object]) -> None:
        """Inverse of ``save`` on a coupling built on the same mesh."""

    def inherit(self, old: Coupling, carry: Carriers) -> None:
        """Continue ``old`` (the same coupling on the mesh before a remesh)."""

    def reset_factorisation(self) -> None:
        """Forget the symbolic LU of any system it solves (a fresh analysis next time)."""


class CouplingSpec(Protocol):
    """The frozen values a coupling is built from, on each mesh of a run; ``fields`` are
    what the couplings built before it hand the law (a fluidity reads the share of layer
    material to blend two materials' coefficients)."""

    def build(self, site: Site, fields: Mapping[str, Any]) -> Coupling: ...
