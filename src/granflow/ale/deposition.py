"""Deposition of the free surface onto the rigid bed and the wall (section 3.3, Figure 2).

The step is limited so that no free boundary node crosses the bed (the profile z_b(x):
the level z = 0 of the paper's columns) or the wall (x = 0 there): the first node to reach
one lands on it exactly at the end of the shortened step, and once a surface segment lies
on the bed or the wall it is relabelled and takes that boundary's conditions (friction and
u.N = 0). On a bed with slope changes a node lands on whichever segment it reaches first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from granflow.ale.free_surface import BoundaryChain
from granflow.geometry.labels import BED, SURFACE, WALL
from granflow.geometry.profile import BedProfile, Line

LANDING_TOLERANCE = 1e-9  # relative slack on the landing time of a node


@dataclass(frozen=True)
class Support:
    """What the free surface lands on: the bed and, if there is one, the left wall."""

    bed: BedProfile
    wall: Line | None = None


# the paper's columns: the bed z = 0 and the wall x = 0
LEVEL = Support(BedProfile.flat(), Line.through(np.zeros(2), np.array([0.0, 1.0]),
                                                np.array([1.0, 0.0])))


def landing_time(xy: np.ndarray, velocity: np.ndarray, vertices: np.ndarray,
                 support: Support = LEVEL) -> np.ndarray:
    """Time for each vertex to reach the bed or the wall moving at ``velocity`` (inf if
    never)."""
    p, w = xy[vertices], velocity[vertices]
    t_bed = support.bed.landing_time(p, w)
    if support.wall is None:
        return t_bed
    return np.minimum(t_bed, support.wall.landing_time(p, w))


def limit_step(xy: np.ndarray, velocity: np.ndarray, candidates: np.ndarray,
               dt: float, support: Support = LEVEL) -> tuple[float, np.ndarray]:
    """dt shortened to the first landing of a ``candidates`` vertex, and the vertices that
    land within it (to be snapped onto the bed or the wall by ``snap_landed``)."""
    times = landing_time(xy, velocity, candidates, support)
    if times.size and float(times.min()) < dt:
        dt = float(times.min())
    return dt, candidates[times <= dt * (1 + LANDING_TOLERANCE)]


def snap_landed(xy: np.ndarray, landed: np.ndarray, support: Support = LEVEL) -> None:
    """Put each landed vertex exactly on the bed or the wall, whichever it is nearer."""
    for v in landed:
        p = xy[v:v + 1]
        bed = float(support.bed.height(p)[0])
        wall = abs(float(support.wall.height(p)[0])) if support.wall is not None else np.inf
        xy[v] = (support.bed if bed <= wall else support.wall).project(p)[0]  # type: ignore[union-attr]


def relabel_deposited(chain: BoundaryChain, tol: float, support: Support = LEVEL) -> int:
    """Relabel surface segments lying on the bed (within tol above it, ends and middle)
    or on the wall (ends within tol of it), in place in the mesh; returns how many."""
    mesh = chain.mesh
    xy = mesh.ngmesh.Coordinates()
    e1 = mesh.ngmesh.Elements1D().NumPy()
    seg = e1["nodes"][:, :2].astype(np.int64) - 1
    surface = e1["index"] == chain.index[SURFACE]
    on_bed = surface.copy()
    if surface.any():
        ends = xy[seg[surface]]
        heights = support.bed.height(ends.reshape(-1, 2)).reshape(-1, 2)
        middle = support.bed.height(ends.mean(axis=1))
        on_bed[surface] = np.all(heights <= tol, axis=1) & (middle <= tol)
    on_wall = np.zeros_like(surface)
    if support.wall is not None and surface.any():
        ends = xy[seg[surface]].reshape(-1, 2)
        on_wall[surface] = np.all(support.wall.height(ends).reshape(-1, 2) <= tol, axis=1)
    e1["index"][on_bed] = chain.index[BED]
    e1["index"][on_wall & ~on_bed] = chain.index[WALL]
    return int(on_bed.sum() + (on_wall & ~on_bed).sum())
