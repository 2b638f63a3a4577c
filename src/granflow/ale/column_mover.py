"""Mesh motion of a column: ALE move, deposition, area conservation, surface tension.

The free-surface treatments live in their own modules: deposition (``ale/deposition.py``),
surface tension (``ale/surface_tension.py``), remeshing (``ale/remesh.py``, called by the
loop on a typed ``MoveFailure``).

Section 3.3: the step is limited so that no boundary node crosses the bed or the wall; a
surface node that reaches the bed becomes a bed node and its edges change boundary
condition (Figure 2). Nodes on the bed and walls (and on the far end of an erodible layer,
and on a gate) are kept exactly on them: a bed node is put back on the nearest point of
the bed profile, so that it slides along the bed and through its corners. After each move
the numerical surface tension of section 3.4 (``ale/surface_tension.py``), when present,
is set on the moved surface. A gate's lower end rises with time; its edges below it become
free surface (``geometry/gate.py``).
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from typing import ClassVar

import ngsolve as ngs
import numpy as np

from granflow.ale.deposition import (
    LEVEL,
    Support,
    limit_step,
    relabel_deposited,
    snap_landed,
)
from granflow.ale.free_surface import (
    AREA,
    BoundaryChain,
    PolygonMeasure,
    bed_overlaps,
    conserve_above,
    crossing_segments,
    overlap_pocket,
    pocket,
)
from granflow.ale.mesh_motion import (
    AleMover,
    MeshVelocitySolver,
    MoveFailure,
    VelocityHistory,
)
from granflow.ale.remesh import straddled_corners
from granflow.ale.surface_tension import SurfaceTension, TensionState
from granflow.fem.sampling import triangles
from granflow.geometry.gate import Gate
from granflow.geometry.labels import BED, END, GATE, SURFACE, WALL
from granflow.geometry.profile import Line
from granflow.state.spec import (
    COUNT,
    REAL,
    TIME,
    Share,
    dataclass_of,
    may_lack,
    number,
    or_none,
)

CROSS = 1e-12   # m: a node this far beyond the bed or a wall has crossed it
MASS_FIXES = 8   # rounds of the free-surface fix at most when it conserves a mass (below)
STRADDLE = 1e-5   # a bed edge this far (x the bed's extent) from a corner it spans: remesh


def _no_excess(xy: np.ndarray) -> float:
    return 0.0


class ColumnMover(AleMover):
    """AleMover with the deposition procedure and an optional conserving correction.

    The correction moves the free surface so that the section's measure (the area, or
    the revolved volume) plus ``excess(xy)`` keeps its initial value: the measure itself
    for an incompressible flow (``excess`` = 0); with a packing fraction, the mass, the
    measure it would fill at its initial packing (``Coupling.volume_excess``). The excess
    moves a little with the surface cells, so the fix is repeated until its target stops
    changing (one round when the excess is 0). A packing that changed over the accepted
    step (or in a remesh's transfer) changes the excess: the fix is applied again to the
    accepted state then, so that every accepted state holds the initial mass; the target
    of an incompressible flow never changes, and its runs are the paper's."""

    share: ClassVar[Share] = {       # its share of a checkpoint (``save_state``)
        "initial_area": number(0.0, above=True), "initial_excess": may_lack(REAL),
        "clock": may_lack(TIME),
        "gate_opened": may_lack(COUNT), "relabelled_segments": COUNT, "limited_steps": COUNT,
        "velocity_solves": COUNT, "correction_abs": REAL, "correction_net": REAL,
        "tension": or_none(dataclass_of(TensionState))}

    def __init__(self, mesh: ngs.Mesh, velocity_solver: MeshVelocitySolver,
                 source: ngs.GridFunction, flow: VelocityHistory, target: ngs.GridFunction,
                 extrapolate: bool = False, conserve_volume: bool = True,
                 tension: SurfaceTension | None = None,
                 measure: PolygonMeasure = AREA, support: Support = LEVEL,
                 gate: Gate | None = None, gate_speed: ngs.Parameter | None = None,
                 excess: Callable[[np.ndarray], float] = _no_excess) -> None:
        super().__init__(mesh, velocity_solver, source, flow, target, extrapolate)
        self.chain = BoundaryChain(mesh)
        self.tension = tension
        self.support, self.gate, self.gate_speed = support, gate, gate_speed
        end = self.chain.vertices(END)
        self.end_x = float(mesh.ngmesh.Coordinates()[end, 0].max()) if end.size else np.inf
        self.end = _end_line(mesh.ngmesh.Coordinates()[end], support) if end.size else None
        self.clock = 0.0          # time of the accepted state (the gate's opening reads it)
        self.gate_opened = 0      # gate edges that became free surface
        self._dt = 0.0
        self.conserve_volume = conserve_volume
        self.measure = measure      # the area, or the revolved volume in axisymmetry
        self.initial_area = measure.size(mesh.ngmesh.Coordinates(), self.chain.segments)
        self.excess = excess
        self.initial_excess = excess(mesh.ngmesh.Coordinates())
        self.landed: np.ndarray = np.empty(0, dtype=np.int64)
        self.relabelled_segments = 0
        self.limited_steps = 0
        self._tension_accepted: TensionState | None = None   # the tension before the move
        # the surface vertices a refused move folded over (``pocket``): the remesh cuts them
        self.fold_pocket: np.ndarray = np.empty(0, dtype=np.int64)
        self._overlapping: np.ndarray | None = None   # the last check's overlapping bed segments
        # the volume fix: relative area restored at the last move, and summed over the run
        # (|.| and signed), so that a volume error of 0 by construction says what it cost
        self.step_correction = 0.0
        self._fixed_to: float | None = None   # the target of the step's fix
        self.correction_abs = 0.0
        self.correction_net = 0.0

    def inherit(self, other: ColumnMover) -> None:
        """Carry the reference area, the counters and the tension switch over a remesh;
        the mass of a packing that the transfer changed is restored on the new mesh."""
        self.restore_state(other.save_state())
        xy = self.mesh.ngmesh.Coordinates()
        if self.conserve_volume and self.excess(xy) != 0.0:
            self._conserve(xy, self._movable(np.empty(0, dtype=np.int64)))

    def save_state(self) -> dict[str, object]:
        """Reference area, counters and the surface-tension switch (for a checkpoint)."""
        return {"initial_area": self.initial_area, "initial_excess": self.initial_excess,
                "clock": self.clock,
                "gate_opened": self.gate_opened,
                "relabelled_segments": self.relabelled_segments,
                "limited_steps": self.limited_steps, "velocity_solves": self.velocity_solves,
                "correction_abs": self.correction_abs, "correction_net": self.correction_net,
                "tension": copy.deepcopy(self.tension.state) if self.tension else None}

    def restore_state(self, state: dict[str, object]) -> None:
        for key in ("initial_area", "relabelled_segments", "limited_steps", "velocity_solves",
                    "correction_abs", "correction_net"):
            setattr(self, key, state[key])
        self.clock = float(state.get("clock", 0.0))      # type: ignore[arg-type]
        self.initial_excess = float(state.get("initial_excess", 0.0))  # type: ignore[arg-type]
        self.gate_opened = int(state.get("gate_opened", 0))   # type: ignore[call-overload]
        if self.tension is not None and state["tension"] is not None:
            self.tension.state = copy.deepcopy(state["tension"])  # type: ignore[assignment]

    def prepare(self, dt: float) -> float:
        """w for this step, and dt shortened so that no boundary node crosses bed or wall.

        With an extrapolated w (which depends on dt), w is recomputed for the shortened
        step and the node found landing is snapped onto the bed by ``move``.
        """
        self._prepare_w(dt)
        assert self.w_vertices is not None
        xy = self.mesh.ngmesh.Coordinates()
        bed, wall = self._on_bed(), self._on_wall()
        held = np.union1d(np.union1d(bed, wall), np.union1d(self._on_end(), self._on_gate()))
        candidates = np.setdiff1d(np.unique(self.chain.segments), held)
        limited, self.landed = limit_step(xy, self.w_vertices, candidates, dt, self.support)
        if limited < dt:
            dt = limited
            self.limited_steps += 1
            if self.extrapolate:   # w for the shortened step; the landed set is kept
                self._prepare_w(dt)
        if self.gate is not None and self.gate_speed is not None:   # at t^{n+1}, as (3.2)
            self.gate_speed.Set(self.gate.law.velocity(self.clock + dt))
        return dt

    def _prepare_w(self, dt: float) -> None:
        super().prepare(dt)
        self._pin_contact_points(dt)
        self._hold_bed_corners()

    def _hold_bed_corners(self) -> None:
        """A bed node at a corner of the bed profile stays there: w.N = u.N = 0 on both
        segments (3.6) is w = 0 (the discrete u.N, imposed by a penalty, is not quite 0 and
        would let it slide off). A contact point there still moves with the material."""
        corners = self.support.bed.corners()
        if not len(corners):
            return
        assert self.w_vertices is not None
        xy = self.mesh.ngmesh.Coordinates()
        bed = np.setdiff1d(self.chain.vertices(BED), self.chain.vertices(SURFACE))
        d = np.hypot(*(xy[bed][:, None, :] - corners[None]).transpose(2, 0, 1)).min(axis=1)
        scale = float(np.ptp(self.support.bed.points, axis=0).max())
        self.w_vertices[bed[d <= 1e-9 * scale]] = 0.0

    def _pin_contact_points(self, dt: float) -> None:
        """Where the surface meets the bed or the wall, w = u (pure Lagrangian, section 3.2).

        (3.6) gives this at every normal discontinuity; at a thin front the bed and surface
        normals are almost opposite and the penalty leaves w_x nearly free, so the contact
        point would drift along the bed while the material there is at rest.
        """
        assert self.w_vertices is not None
        surface = self.chain.vertices(SURFACE)
        walls = np.union1d(np.union1d(self._on_bed(), self._on_wall()),
                           np.union1d(self._on_end(), self._on_gate()))
        corners = np.intersect1d(surface, walls)
        self.w_vertices[corners] = self.source_at_vertices(dt)[corners]

    def move(self, dt: float) -> None:
        super().move(dt)
        self._dt = dt
        self.fold_pocket = np.empty(0, dtype=np.int64)
        xy = self.mesh.ngmesh.Coordinates()
        bed, wall = self._on_bed(), self._on_wall()
        end, gate = self._on_end(), self._on_gate()
        xy[bed] = self.support.bed.project(xy[bed])
        for line, on in ((self.support.wall, wall), (self.end, end),
                         (self.gate.line if self.gate else None, gate)):
            if line is not None and on.size:
                xy[on] = line.project(xy[on])
                xy[np.intersect1d(on, bed)] = line.point   # the corner with the bed
        snap_landed(xy, self.landed, self.support)   # a landing node lands exactly on it
        if self.conserve_volume:
            pinned = np.union1d(np.union1d(bed, wall), np.union1d(end, self.landed))
            pinned = np.union1d(pinned, gate)
            movable = np.setdiff1d(self.chain.free_vertices(), pinned)
            self.step_correction = self._conserve(xy, movable)
        if self.tension is not None:
            self._tension_accepted = copy.copy(self.tension.state)   # scalars only
            self.tension.update(self.chain.surface_chains(), self.pressure_under)

    def _movable(self, landed: np.ndarray) -> np.ndarray:
        """The surface vertices the fix may move: none on the bed, a wall, the layer's
        end or the gate, nor one landing on the bed in this step."""
        pinned = np.union1d(np.union1d(self._on_bed(), self._on_wall()),
                            np.union1d(self._on_end(), landed))
        return np.setdiff1d(self.chain.free_vertices(), np.union1d(pinned, self._on_gate()))

    def _target(self, xy: np.ndarray) -> float:
        """The measure the fix restores with the vertices at ``xy`` (class docstring)."""
        return self.initial_area + (self.initial_excess - self.excess(xy))

    def _conserve(self, xy: np.ndarray, movable: np.ndarray) -> float:
        """The free-surface fix (class docstring): the relative change of the measure it
        applied, summed over its rounds."""
        applied, target = 0.0, None
        for _ in range(MASS_FIXES):
            wanted = self._target(xy)
            if wanted == target:
                break
            target = wanted
            applied += conserve_above(xy, self.chain.segments, movable, target, lambda p:
                                      self.support.bed.height(p) + CROSS, measure=self.measure)
        self._fixed_to = target
        return applied

    def undo(self) -> None:
        """Back to the accepted mesh, and the surface tension's switch with it: a retry
        decides on and off (and whether that is a jump) from the last accepted step."""
        super().undo()
        if self.tension is not None and self._tension_accepted is not None:
            self.tension.state = self._tension_accepted

    def forcing_jumped(self) -> bool:
        """Whether the last move switched the surface tension on or off (only that: the
        fold's node moving, a new gamma0 or the gate opening change the forcing less)."""
        before = self._tension_accepted
        return (self.tension is not None and before is not None
                and self.tension.state.active != before.active)

    def pressure_under(self, vertices: np.ndarray) -> float:
        """Mean pressure p^n over the triangles with an edge between two of ``vertices``
        (surface nodes): the first cells under that part of the surface (section 3.4)."""
        tri = triangles(self.mesh)
        under = np.isin(tri, vertices).sum(axis=1) >= 2
        p = self.flow.previous.components[1].vec.FV().NumPy()[:self.mesh.nv]
        return float(p[tri[under]].mean()) if under.any() else 0.0

    def _on_bed(self) -> np.ndarray:
        """Vertices on bed segments, and landed surface vertices not yet on one."""
        xy = self.mesh.ngmesh.Coordinates()
        landed = np.flatnonzero(self.support.bed.height(xy) <= 0.0)
        return np.union1d(self.chain.vertices(BED), landed)

    def _on_end(self) -> np.ndarray:
        return self.chain.vertices(END)

    def _on_gate(self) -> np.ndarray:
        return self.chain.vertices(GATE) if self.gate is not None else np.empty(0, np.int64)

    def _on_wall(self) -> np.ndarray:
        if self.support.wall is None:
            return self.chain.vertices(WALL)
        xy = self.mesh.ngmesh.Coordinates()
        return np.union1d(self.chain.vertices(WALL),
                          np.flatnonzero(self.support.wall.height(xy) <= 0.0))

    def check(self) -> MoveFailure | None:
        problem = super().check()
        xy = self.mesh.ngmesh.Coordinates()
        if problem is not None:
            self.fold_pocket = self._overlap_pocket(xy)   # cut by the remesh, if any
            return problem
        lines = [line for line in (self.support.wall, self.end) if line is not None]
        if (np.any(self.support.bed.height(xy) < -CROSS)
                or any(np.any(line.height(xy) < -CROSS) for line in lines)):
            return MoveFailure.CROSSED_WALL
        crossing = crossing_segments(xy, self.chain.segments)
        if len(crossing):
            self.fold_pocket = pocket(self.chain.segments, self.chain.labels(),
                                      self.chain.index[SURFACE], crossing)
            return MoveFailure.SELF_INTERSECTS
        self.fold_pocket = self._overlap_pocket(xy)
        return MoveFailure.SELF_INTERSECTS if self._overlapping is not None else None

    def _overlap_pocket(self, xy: np.ndarray) -> np.ndarray:
        """The pocket of surface a move landed on bed the material covers (two bed segments
        overlapping: collinear, which the crossing test does not see), else none."""
        bed = self.support.bed
        pairs = bed_overlaps(xy, self.chain.segments, bed.height, bed.arc_length, CROSS)
        self._overlapping = pairs if len(pairs) else None
        if not len(pairs):
            return np.empty(0, dtype=np.int64)
        return overlap_pocket(self.chain.segments, self.chain.labels(),
                              self.chain.index[SURFACE], pairs)

    def conserve_again(self, xy: np.ndarray) -> float:
        """The accepted step's free-surface fix applied again to the vertices at ``xy``,
        after something the mover does not see changed the measure it keeps (the layer's
        share, with two packings): the relative change it applied."""
        return self._conserve(xy, self._movable(self.landed))

    def after_accept(self) -> None:
        xy = self.mesh.ngmesh.Coordinates()
        if self.conserve_volume and self._fixed_to is not None and (
                self._target(xy) != self._fixed_to):      # the packing changed in the step
            self.step_correction += self._conserve(xy, self._movable(self.landed))
        self._fixed_to = None
        self.correction_abs += abs(self.step_correction)
        self.correction_net += self.step_correction
        if self.tension is not None and self.tension.state.active:
            self.tension.state.active_steps += 1
        self._tension_accepted = None
        self.relabelled_segments += relabel_deposited(self.chain, 1e-12, self.support)
        self.clock += self._dt
        if self.gate is not None:
            self.gate_opened += self._open_gate()
        super().after_accept()

    def _open_gate(self) -> int:
        """Gate edges whose middle the gate's lower end has passed become free surface
        (their end on the gate a contact point): the opening is resolved to half an edge."""
        assert self.gate is not None
        if GATE not in self.chain.index:       # the gate has cleared the mass
            return 0
        e1 = self.mesh.ngmesh.Elements1D().NumPy()
        on_gate = np.flatnonzero(e1["index"] == self.chain.index[GATE])
        if not on_gate.size:
            return 0
        xy = self.mesh.ngmesh.Coordinates()
        middle = xy[e1["nodes"][on_gate, :2].astype(np.int64) - 1].mean(axis=1)
        opened = on_gate[~self.gate.closed(middle, self.clock)]
        e1["index"][opened] = self.chain.index[SURFACE]
        return len(opened)

    def straddles_corner(self) -> bool:
        """Whether a bed edge passes over a corner of the bed profile (a node slid through
        it): a remesh then makes the corner a vertex again (``ale/remesh.py``)."""
        bed = self.support.bed
        if bed.segments == 1:
            return False
        e1 = self.mesh.ngmesh.Elements1D().NumPy()
        on_bed = e1["index"] == self.chain.index[BED]
        nodes = e1["nodes"][on_bed, :2].astype(np.int64) - 1
        held = ~np.isin(nodes, self.chain.vertices(SURFACE))
        scale = float(np.ptp(bed.points, axis=0).max())
        ends = self.mesh.ngmesh.Coordinates()[nodes]
        return straddled_corners(ends, held, bed, STRADDLE * scale) > 0

    def area(self) -> float:
        """The conserved measure now: the area (m^2 per metre), or the revolved volume (m^3)."""
        return self.measure.size(self.mesh.ngmesh.Coordinates(), self.chain.segments)


def _end_line(points: np.ndarray, support: Support) -> Line:
    """The far end of an erodible layer through its mesh vertices: a vertical line at their
    largest x on the level bed (as the layer was built), else normal to the bed at its foot."""
    if support.bed.level or np.ptp(points[:, 0]) == 0:
        x = float(points[:, 0].max())
        return Line.through(np.array([x, support.bed.points[0, 1]]), np.array([0.0, 1.0]),
                            np.array([x - 1.0, 0.0]))
    foot = points[np.argmin(support.bed.height(points))]
    k = int(support.bed.segment_of(np.array([foot[0]]))[0])
    return Line.through(support.bed.project(foot)[0], support.bed.normal(k),
                        foot - support.bed.tangent(k))
