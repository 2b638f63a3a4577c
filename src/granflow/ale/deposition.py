"""Deposition of the free surface onto the rigid bed and the wall (section 3.3, Figure 2).

The step is limited so that no free boundary node crosses the bed (Z = 0) or the wall
(X = 0): the first node to reach one lands on it exactly at the end of the shortened
step, and once a surface segment lies on the bed or the wall it is relabelled and takes
that boundary's conditions (friction and u.N = 0).
"""

from __future__ import annotations

import numpy as np

from granflow.ale.free_surface import BoundaryChain
from granflow.geometry.mesh import BED, SURFACE, WALL

LANDING_TOLERANCE = 1e-9  # relative slack on the landing time of a node


def landing_time(xy: np.ndarray, velocity: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Time for each vertex to reach Z = 0 or X = 0 moving at ``velocity`` (inf if never)."""
    p, w = xy[vertices], velocity[vertices]
    with np.errstate(divide="ignore", invalid="ignore"):
        t_bed = np.where(w[:, 1] < 0, p[:, 1] / -w[:, 1], np.inf)
        t_wall = np.where(w[:, 0] < 0, p[:, 0] / -w[:, 0], np.inf)
    return np.minimum(t_bed, t_wall)


def limit_step(xy: np.ndarray, velocity: np.ndarray, candidates: np.ndarray,
               dt: float) -> tuple[float, np.ndarray]:
    """dt shortened to the first landing of a ``candidates`` vertex, and the vertices that
    land within it (to be snapped onto the bed or the wall by ``snap_landed``)."""
    times = landing_time(xy, velocity, candidates)
    if times.size and float(times.min()) < dt:
        dt = float(times.min())
    return dt, candidates[times <= dt * (1 + LANDING_TOLERANCE)]


def snap_landed(xy: np.ndarray, landed: np.ndarray) -> None:
    """Put each landed vertex exactly on the bed or the wall, whichever it is nearer."""
    for v in landed:
        if xy[v, 1] <= abs(xy[v, 0]):
            xy[v, 1] = 0.0
        else:
            xy[v, 0] = 0.0


def relabel_deposited(chain: BoundaryChain, tol: float) -> int:
    """Relabel surface segments lying on the bed (Z <= tol) or wall (X <= tol), in place in
    the mesh; returns how many."""
    mesh = chain.mesh
    xy = mesh.ngmesh.Coordinates()
    e1 = mesh.ngmesh.Elements1D().NumPy()
    seg = e1["nodes"][:, :2].astype(np.int64) - 1
    surface = e1["index"] == chain.index[SURFACE]
    on_bed = surface & np.all(xy[seg, 1] <= tol, axis=1)
    on_wall = surface & np.all(xy[seg, 0] <= tol, axis=1)
    e1["index"][on_bed] = chain.index[BED]
    e1["index"][on_wall & ~on_bed] = chain.index[WALL]
    return int(on_bed.sum() + (on_wall & ~on_bed).sum())
