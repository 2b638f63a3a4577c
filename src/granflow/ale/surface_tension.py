"""Local numerical surface tension at the most curved point of the free surface (3.8)-(3.11).

Over an erodible layer the front of the spreading mass folds over itself (Figure 4, right)
and the ALE move cannot follow a fold. The paper imposes (2.11), sigma N = gamma N, on the
free surface with gamma = gamma_0 C (3.8): C is the discrete curvature of the surface
chain, negative where the domain is locally convex (3.9)-(3.10), and gamma_0 is non-zero
only within ``delta`` nodes of the node i_c of largest curvature (3.11). Like a physical
surface tension it pulls a convex bulge in and pushes a concave corner out, so a fold is
straightened. It is a numerical device: gamma_0-bar is of the order of the pressure under
the surface times the mesh size. On a mesh graded finer over a layer than over the column,
"the mesh size" is either ``mesh.size`` (``length = "mesh_size"``) or, as the paper's
"position-dependent gamma_0" allows, each node's own edge length, the denominator of C in
(3.10) (``length = "local_edge"``): then gamma_i = p-bar w_i delta theta_i, the pressure
times the turning angle wherever the mesh is finer, and no longer grows with mesh.size over
the local edge.

When it acts (the paper gives no rule): at a step where the surface turns by at least
``trigger_angle_deg`` at a concave node (delta theta >= trigger; default 90 deg: the
surface turns back past the perpendicular into the domain, which is where a fold begins;
0 = at every step). Once on it stays on while the largest concave turn is at least
``release_angle_deg`` (hysteresis; default 45 deg), so that it does not toggle about one
threshold as it straightens a fold: each switch is a jump in the surface traction, which
the step-error control answers with smaller steps. i_c is the node of largest curvature
C, signed as in (3.10), as the paper says: the most concave node, i.e. the fold. A convex
nose is left alone: over a rigid bed the overturning front is a convex nose that
deposition (Figure 2) lands on the bed, and a tension there acts as one always on does,
shortening the runout (docs/verification.md, the erodible bed; benchmarks/erodible.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import ngsolve as ngs
import numpy as np


def turning_angles(points: np.ndarray) -> np.ndarray:
    """delta theta_i of (3.9) at the interior nodes 1..n-2 of the chain ``points`` (n, 2).

    R_i = P_i - P_{i-1}; the angle from R_i to R_{i+1}, positive counter-clockwise. The
    chain runs with the domain on its right (from the wall to the front), so a convex
    domain turns clockwise: negative.
    """
    r = np.diff(points, axis=0)
    a, b = r[:-1], r[1:]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]          # R_{i+1} . R_i^perp
    dot = np.sum(a * b, axis=1)
    norms = np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)
    return 2.0 * np.arctan2(cross, norms + dot)


def node_lengths(points: np.ndarray) -> np.ndarray:
    """Each node's length in (3.10), the mean of its two edges (the two ends: their one)."""
    r = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return np.concatenate([r[:1], 0.5 * (r[:-1] + r[1:]), r[-1:]])


def curvature(points: np.ndarray) -> np.ndarray:
    """C_i of (3.10) at every node of the chain (0 at its two ends)."""
    c = np.zeros(len(points))
    c[1:-1] = turning_angles(points) / node_lengths(points)[1:-1]
    return c


def tension_profile(n: int, critical: int, delta: float) -> np.ndarray:
    """gamma_{0,i} / gamma_0-bar of (3.11): (max(0, 1 - ((i - i_c)/delta)^2))^2."""
    i = np.arange(n)
    return np.maximum(0.0, 1.0 - ((i - critical) / delta) ** 2) ** 2


LENGTHS = ("mesh_size", "local_edge")   # what gamma_0-bar scales with


@dataclass
class TensionState:
    """What the last update did (for diagnostics and the run summary)."""

    active: bool = False
    critical_x: float = float("nan")
    max_turn_deg: float = 0.0  # largest concave turn of the surface at the last update
    gamma0: float = 0.0  # gamma_0-bar at the critical node
    pressure: float = 0.0  # the pressure gamma_0-bar was taken from ("auto")
    active_steps: int = 0  # accepted steps with the tension on (counted by the mover)


class SurfaceTension:
    """Writes gamma = gamma_{0,i} C_i at the surface vertices into a P1 field on the mesh.

    ``field`` is what the momentum equation uses as the traction gamma N on the free surface
    (``fem.forms.SurfaceTraction``); it is zero away from the fold and when off.
    """

    def __init__(self, field: ngs.GridFunction, delta: float, gamma0: float | str,
                 trigger_angle_deg: float, mesh_size: float,
                 release_angle_deg: float | None = None,
                 length: str = "mesh_size") -> None:
        self.field = field
        self.delta = delta
        self.gamma0 = gamma0
        self.trigger = np.radians(trigger_angle_deg)
        release = trigger_angle_deg if release_angle_deg is None else release_angle_deg
        self.release = np.radians(min(release, trigger_angle_deg))
        self.mesh_size = mesh_size
        if length not in LENGTHS:
            raise ValueError(f"surface_tension.length = {length!r}: one of {LENGTHS}")
        self.length = length
        self.state = TensionState()

    def update(self, chains: list[np.ndarray],
               pressure_under: Callable[[np.ndarray], float]) -> None:
        """Set gamma on the surface chains (vertex indices, each from wall side to front).

        Deposition can split the surface into several chains; angles are taken within each,
        i_c over all of them. ``pressure_under(vertices)`` is the mean pressure in the cells
        under those surface vertices: with gamma0 = "auto", gamma0-bar is that pressure
        under the nodes where the tension acts (within delta of i_c) times the length
        (``mesh.size``, or each node's edge length of (3.10)).
        """
        values = self.field.vec.FV().NumPy()
        values[:] = 0.0
        xy = self.field.space.mesh.ngmesh.Coordinates()
        chains = [c for c in chains if len(c) >= 3]
        was_active = self.state.active
        threshold = self.release if was_active else self.trigger
        self.state.active = False
        if not chains:
            return
        turns = np.concatenate([turning_angles(xy[c]) for c in chains])
        self.state.max_turn_deg = float(np.degrees(turns.max()))
        if turns.max() < threshold:
            return
        curv = [curvature(xy[c]) for c in chains]
        k = int(np.argmax([c.max() for c in curv]))
        chain, c = chains[k], curv[k]
        critical = int(np.argmax(c))
        profile = tension_profile(len(chain), critical, self.delta)
        if self.gamma0 == "auto":
            under = pressure_under(chain[profile > 0])
            # Under an acting tension a pressure <= 0 is the tension's own pull, not the
            # absence of load: keep its last pressure (a gamma0 set to 0 there switches the
            # tension off, the pressure comes back and it switches on: every other step).
            held = self.state.pressure if was_active else 0.0
            pressure = under if under > 0 else held
            gamma0 = pressure * (node_lengths(xy[chain]) if self.length == "local_edge"
                                 else self.mesh_size)
        else:
            pressure = float("nan")
            gamma0 = float(self.gamma0) * (node_lengths(xy[chain]) / self.mesh_size
                                           if self.length == "local_edge" else 1.0)
        values[chain] = gamma0 * profile * c
        self.state.pressure = pressure
        self.state.gamma0 = float(np.broadcast_to(gamma0, profile.shape)[critical])
        self.state.active = True
        self.state.critical_x = float(xy[chain[critical], 0])
