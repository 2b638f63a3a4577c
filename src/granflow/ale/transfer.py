"""Field transfer across a remesh: nodal interpolation that stays inside the old domain,
then a discrete divergence-free projection of the velocity.

Why not ``GridFunction.Set`` from the old field: a remesh straightens nearly flat surface
stretches, so parts of the new domain lie (slightly) outside the old one, where NGSolve
evaluates the old field to garbage without an error; and an interpolated velocity is not
discretely divergence-free on the new mesh, so the first implicit step after a remesh
would project it with a pressure spike of order rho |div u| h^2 / dt. With the paper's
dt = 1e-4 s that spike enters the yield stress kappa = sqrt(2) mu_s [p]_+ (2.4) and the
friction load, and perturbs the flow well beyond the interpolation error itself.
"""

from __future__ import annotations

import ngsolve as ngs
import numpy as np
from scipy.spatial import cKDTree

from granflow.fem.locator import PointLocator
from granflow.fem.measure import PLANE, Coordinates

INWARD_NUDGE = 1e-9  # relative to the segment length: how far inside a clamped point sits


def boundary_segments(mesh: ngs.Mesh) -> np.ndarray:
    """(ns, 2) vertex indices of the boundary segments, counter-clockwise."""
    return mesh.ngmesh.Elements1D().NumPy()["nodes"][:, :2].astype(np.int64) - 1


def clamp_inside(mesh: ngs.Mesh, points: np.ndarray,
                 locator: PointLocator | None = None) -> np.ndarray:
    """Each point moved onto the nearest boundary point of ``mesh`` (just inside) when it
    lies outside the mesh; points inside are returned unchanged.

    Vectorised (a remesh of a long erodible layer transfers tens of thousands of points,
    thousands of them outside, against thousands of boundary segments): one
    point location for all points (``locator``, the mesh's, made here if not given), and
    for those outside only the segments a k-d tree of segment midpoints cannot rule out.
    The nearest segment is the same as an all-pairs search would find, ties going to the
    lowest segment number.
    """
    out = np.array(points, dtype=float)
    element, _ = (locator or PointLocator(mesh)).locate(out)
    outside = np.flatnonzero(element < 0)
    if outside.size == 0:
        return out
    xy = mesh.ngmesh.Coordinates()
    seg = boundary_segments(mesh)
    a, b = xy[seg[:, 0]], xy[seg[:, 1]]
    d = b - a
    length2 = d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]
    tree = cKDTree(0.5 * (a + b))
    p = out[outside]
    _, first = tree.query(p)                                   # a segment close to each point
    bound = np.sqrt(_distance2(p, a[first], d[first], length2[first])[0])
    # any segment nearer than ``bound`` has its midpoint within bound + half its length
    reach = (bound + 0.5 * np.sqrt(length2.max())) * (1 + 1e-9)
    lists = tree.query_ball_point(p, reach)
    counts = np.fromiter((len(c) for c in lists), dtype=np.int64, count=len(lists))
    owner = np.repeat(np.arange(len(lists)), counts)
    cand = np.concatenate([np.asarray(c, dtype=np.int64) for c in lists])
    dist2, nearest = _distance2(p[owner], a[cand], d[cand], length2[cand])
    order = np.lexsort((cand, dist2, owner))       # per point: nearest, then lowest number
    pick = order[np.searchsorted(owner[order], np.arange(len(lists)))]
    k = cand[pick]
    inward = np.column_stack([-d[k, 1], d[k, 0]])  # left of a counter-clockwise edge
    out[outside] = nearest[pick] + INWARD_NUDGE * inward
    return out


def _distance2(p: np.ndarray, a: np.ndarray, d: np.ndarray,
               length2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Squared distance from points p to segments a + s d (row by row), and the nearest
    points; the same arithmetic, in the same order, as the all-pairs search it replaces."""
    rel = p - a
    s = np.clip((rel[:, 0] * d[:, 0] + rel[:, 1] * d[:, 1]) / length2, 0.0, 1.0)
    nearest = a + s[:, None] * d
    gap = nearest - p
    return gap[:, 0] ** 2 + gap[:, 1] ** 2, nearest


def clamp_all_pairs(mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """The reference for ``clamp_inside`` (a point-by-point search, O(points x segments)): each
    point located alone, each outside point compared with every boundary segment. Kept for
    tests/unit/test_transfer.py and benchmarks/fold_checks.py."""
    xy = mesh.ngmesh.Coordinates()
    seg = boundary_segments(mesh)
    a, d = xy[seg[:, 0]], xy[seg[:, 1]] - xy[seg[:, 0]]
    out = np.array(points, dtype=float)
    for i, p in enumerate(out):
        if mesh(float(p[0]), float(p[1])).nr >= 0:
            continue
        s = np.clip(np.sum((p - a) * d, axis=1) / np.sum(d * d, axis=1), 0.0, 1.0)
        nearest = a + s[:, None] * d
        k = int(np.argmin(np.sum((nearest - p) ** 2, axis=1)))
        out[i] = nearest[k] + INWARD_NUDGE * np.array([-d[k, 1], d[k, 0]])
    return out


def sample(field: ngs.CoefficientFunction, mesh: ngs.Mesh, points: np.ndarray) -> np.ndarray:
    """Values of ``field`` (living on ``mesh``) at ``points`` clamped into the mesh."""
    locator = PointLocator(mesh)
    return locator.values(field, clamp_inside(mesh, points, locator))


def _edge_midpoints(mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """Midpoints of the mesh edges and the vertex numbers of their ends."""
    xy = mesh.ngmesh.Coordinates()
    ends = np.array([[v.nr for v in e.vertices] for e in mesh.edges], dtype=np.int64)
    return 0.5 * (xy[ends[:, 0]] + xy[ends[:, 1]]), ends


class StateTransfer:
    """What carrying a Taylor-Hood state onto one new mesh needs that does not depend on
    the state: the P2 interpolation's edge geometry and the factorised divergence-free
    projection. A remesh builds one and applies it to each state it carries over
    ((u^n, p^n) and (u^{n-1}, p^{n-1})), so both share one assembly and one factorisation.
    """

    def __init__(self, space: ngs.FESpace, walls: list[str], penalty: float,
                 coords: Coordinates = PLANE) -> None:
        mesh = space.mesh
        self.mesh = mesh
        self.mid, self.ends = _edge_midpoints(mesh)
        scalar = ngs.H1(mesh, order=2)
        self.edge_dofs = np.array([scalar.GetDofNrs(ngs.NodeId(ngs.EDGE, e))[0]
                                   for e in range(len(self.ends))])
        bubble = ngs.GridFunction(scalar)
        bubble.vec.FV().NumPy()[self.edge_dofs] = 1.0
        self._clamped_on: ngs.Mesh | None = None
        self._old: PointLocator | None = None
        self.bubble_mid = self._values(bubble, mesh, self.mid)[:, 0]
        # (u, v) + xi (u.N, v.N)_walls - (lambda, div v) = (u_old, v), (div u, q) = 0, with
        # the measure and divergence of the coordinates (r-weighted in axisymmetry)
        (u, lam), (v, q) = space.TnT()
        n = ngs.specialcf.normal(mesh.dim)
        a = ngs.BilinearForm(space)
        a += coords.dx(u * v - lam * coords.div(v) - q * coords.div(u))
        if walls:
            a += coords.ds(penalty * (u * n) * (v * n),
                           definedon=mesh.Boundaries("|".join(walls)))
        self._source = ngs.GridFunction(space)
        self._rhs = ngs.LinearForm(space)
        self._rhs += coords.dx(self._source.components[0] * v)
        a.Assemble()
        self._matrix = a       # held with its factorisation for the transfer's lifetime
        self._inverse = a.mat.Inverse(space.FreeDofs(), inverse="umfpack")
        self._projected = ngs.GridFunction(space)
        self._clamped_points = (np.empty((0, 2)), np.empty((0, 2)))

    def interpolate_p2(self, target: ngs.GridFunction, at_vertices: np.ndarray,
                       at_mid: np.ndarray) -> None:
        """Set a P2 vector field from its values (n, 2) at the vertices and edge midpoints.

        NGSolve's second-order H1 basis is hierarchical: the edge coefficient is
        (midpoint value - mean of the end values) / bubble(midpoint).
        """
        ends = self.ends
        for c, component in enumerate(target.components):
            vec = component.vec.FV().NumPy()
            vec[:] = 0.0
            vec[: self.mesh.nv] = at_vertices[:, c]
            linear = 0.5 * (at_vertices[ends[:, 0], c] + at_vertices[ends[:, 1], c])
            vec[self.edge_dofs] = (at_mid[:, c] - linear) / self.bubble_mid

    def project_divergence_free(self, state: ngs.GridFunction) -> None:
        """Replace the velocity of ``state`` by its L2-nearest discretely divergence-free
        field with u.N = 0 on the walls (penalty), in place."""
        self._source.vec.data = state.vec
        self._rhs.Assemble()
        self._projected.vec.data = self._inverse * self._rhs.vec
        state.components[0].vec.data = self._projected.components[0].vec

    def apply(self, old: ngs.GridFunction, new: ngs.GridFunction) -> None:
        """(u, p) of ``old`` (on the old mesh) onto ``new`` (on this transfer's mesh)."""
        old_mesh = old.space.mesh
        vertices, mid = self._clamped(old_mesh)
        u_old, p_old = old.components
        self.interpolate_p2(new.components[0], self._values(u_old, old_mesh, vertices),
                            self._values(u_old, old_mesh, mid))
        new.components[1].vec.FV().NumPy()[: len(vertices)] = self._values(
            p_old, old_mesh, vertices)[:, 0]
        self.project_divergence_free(new)

    def _values(self, field: ngs.CoefficientFunction, mesh: ngs.Mesh,
                points: np.ndarray) -> np.ndarray:
        """``field`` at points inside ``mesh``, located by the mesh walk (the old mesh's
        locator made once in ``_clamped``); a transfer on tetrahedra locates its own way."""
        on_old = self._old is not None and mesh is self._clamped_on
        locator = self._old if on_old else PointLocator(mesh)
        assert locator is not None
        return locator.values(field, points)

    def _clamped(self, old_mesh: ngs.Mesh) -> tuple[np.ndarray, np.ndarray]:
        """This mesh's vertices and edge midpoints clamped into ``old_mesh``, and the old
        mesh's point location, made once per old mesh (both carried states live on it)."""
        if self._clamped_on is not old_mesh:
            self._old = PointLocator(old_mesh)
            self._clamped_points = (
                clamp_inside(old_mesh, self.mesh.ngmesh.Coordinates(), self._old),
                clamp_inside(old_mesh, self.mid, self._old))
            self._clamped_on = old_mesh
        return self._clamped_points


def transfer_state(old: ngs.GridFunction, new: ngs.GridFunction, walls: list[str],
                   penalty: float, coords: Coordinates = PLANE) -> None:
    """(u, p) from a Taylor-Hood field on the old mesh to one on the new mesh."""
    StateTransfer(new.space, walls, penalty, coords).apply(old, new)


def transfer_tensor(old: ngs.GridFunction, new: ngs.GridFunction) -> None:
    """A discontinuous tensor field (the augmented Lagrangian's d or lambda) onto the new
    mesh: its values at the new vertices (clamped into the old domain, each taken from one
    adjacent old triangle), linear in between. It smooths the field across edges; d and
    lambda only start the next iteration, which converges to the same step whatever its
    start."""
    mesh, old_mesh = new.space.mesh, old.space.mesh
    entries = ((0, 0), (0, 1), (1, 0), (1, 1))
    scalars = ngs.GridFunction(ngs.L2(old_mesh, order=1) ** len(entries))  # (a point value
    for (i, j), scalar in zip(entries, scalars.components, strict=True):   # of the tensor
        scalar.Set(old[i, j])                                              # space prints noise)
    values = sample(ngs.CF(tuple(scalars.components)), old_mesh, mesh.ngmesh.Coordinates())
    components = []
    for c in range(len(entries)):
        vertex_field = ngs.GridFunction(ngs.H1(mesh, order=1))
        vertex_field.vec.FV().NumPy()[:] = values[:, c]
        components.append(vertex_field)
    new.Set(ngs.CF(tuple(components), dims=(2, 2)))


def transfer_cells(old: ngs.GridFunction, new: ngs.GridFunction) -> None:
    """A piecewise-constant field (L2 of order 0) onto the new mesh: each new triangle
    takes the mean of the old field at four of its points (its centroid and the points
    halfway from it to the corners), each found in the old mesh (clamped into it). Mixing
    the old cells that overlap a new one, as an area average would, without intersecting
    the meshes."""
    mesh, old_mesh = new.space.mesh, old.space.mesh
    corners = mesh.ngmesh.Coordinates()[
        mesh.ngmesh.Elements2D().NumPy()["nodes"][:, :3].astype(np.int64) - 1]
    centroid = corners.mean(axis=1, keepdims=True)
    points = np.concatenate([centroid, 0.5 * (centroid + corners)], axis=1).reshape(-1, 2)
    locator = PointLocator(old_mesh)
    inside = clamp_inside(old_mesh, points, locator)
    values = locator.values(old, inside).reshape(-1, 4)
    new.vec.FV().NumPy()[:] = values.mean(axis=1)


def transfer_vertices(old: ngs.GridFunction, new: ngs.GridFunction) -> None:
    """A continuous P1 field (a nonlocal law's fluidity) onto the new mesh: its values at
    the new vertices, each found in the old mesh (clamped into it)."""
    mesh, old_mesh = new.space.mesh, old.space.mesh
    locator = PointLocator(old_mesh)
    inside = clamp_inside(old_mesh, mesh.ngmesh.Coordinates(), locator)
    new.vec.FV().NumPy()[: mesh.nv] = locator.values(old, inside).reshape(-1)
