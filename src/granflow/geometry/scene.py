"""The set-up of a column run read from its configuration: the bed profile z_b(x), the
walls, the initial mass, an erodible layer following the bed, a gate; and the labelled
polygon of the initial domain.

The mass is a user's polygon (``geometry.mass`` or ``geometry.mass_file``) or a built-in
shape (``geometry.shape``, ``width``, ``height``, ``front_angle_deg``) standing on the
profile's first segment against the wall, in that segment's frame. The left wall stands at
the profile's first point, normal to its first segment (vertical on a level bed). Without a
profile the bed is the level line z = 0 from x = 0, and the built-in shapes give the very
polygons of the paper's Figure 6. Every mistake is a ``GeometryError`` whose one line names
the key and what is wrong, raised before anything is computed.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from granflow.geometry.domains import Polygon, column
from granflow.geometry.gate import MAX_SPEED, Gate, GateLaw
from granflow.geometry.labels import BED, END, GATE, SURFACE, WALL
from granflow.geometry.profile import BedProfile, Line
from granflow.geometry.sources import GeometryError, read_points

ON = 1e-6        # a user's point this close to the bed (x the scene's size) is on it
SAME = 1e-9      # edges this close (x the size) to a line lie on it
GATE_MIN_DEG = 45.0   # the gate's face rises at least this steeply from the bed


@dataclass(frozen=True)
class Scene:
    """Everything a column run needs of its geometry (module docstring)."""

    bed: BedProfile
    wall: Line | None
    polygon: Polygon                 # the labelled initial domain (mass and layer)
    mass: np.ndarray                 # the mass's ring (counter-clockwise, not closed)
    layer: float = 0.0               # erodible layer thickness h_e (normal to the bed)
    layer_end: float = 0.0           # arc length of the bed to the layer's end
    end: Line | None = None          # the layer's far end (normal to the bed there)
    gate: Gate | None = None
    default_bed: bool = True         # the level bed z = 0 from x = 0 (no profile given)
    # a built-in shape on the profile's first segment: the domain in that segment's frame
    # (origin, tangent, normal), where it is meshed, and the frame's polygon
    frame: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    local: Polygon | None = None

    def to_lab(self, local: np.ndarray) -> np.ndarray:
        """Frame coordinates (along, across the first segment) to (x, z)."""
        if self.frame is None:
            return np.array(local, dtype=float)
        o, t, n = self.frame
        pts = np.asarray(local, dtype=float).reshape(-1, 2)
        return o + pts[:, :1] * t + pts[:, 1:] * n

    def to_local(self, xy: np.ndarray) -> np.ndarray:
        """(x, z) to frame coordinates."""
        if self.frame is None:
            return np.array(xy, dtype=float)
        o, t, n = self.frame
        rel = np.asarray(xy, dtype=float).reshape(-1, 2) - o
        return np.column_stack([rel @ t, rel @ n])

    @property
    def size(self) -> float:
        pts = np.asarray(self.polygon.points)
        return float(np.ptp(pts, axis=0).max())

    def layer_top(self, x: np.ndarray) -> np.ndarray:
        """z of the layer's top above x (the bed's z without a layer)."""
        if self.layer <= 0:
            return self.bed.z(x)
        if self.default_bed:
            return np.full(np.shape(np.atleast_1d(x)), self.layer)
        top = self.bed.offset(self.layer, 0.0, max(self.layer_end, 1e-12))
        return np.interp(np.atleast_1d(x), top[:, 0], top[:, 1])

    def layer_line(self) -> np.ndarray:
        """The layer's top from the wall to its end (a polyline)."""
        return self.bed.offset(self.layer, 0.0, self.layer_end)

    def front_x(self) -> float:
        """The mass's rightmost x at t = 0 (X_g, the initial front)."""
        return float(self.mass[:, 0].max())

    def mass_height(self) -> float:
        """The mass's greatest height above the bed."""
        return float(self.bed.height(self.mass).max())


# --- reading the configuration ---------------------------------------------------------

def bed_profile(geo: Any) -> BedProfile | None:
    """The profile given by ``geometry.bed_profile`` or ``bed_profile_file`` (None: the
    level bed z = 0)."""
    if geo.bed_profile is not None and geo.bed_profile_file is not None:
        raise GeometryError("geometry.bed_profile and geometry.bed_profile_file both give "
                            "the bed; set one of them")
    key = "geometry.bed_profile"
    if geo.bed_profile_file is not None:
        key = "geometry.bed_profile_file"
        points = _read(key, geo.bed_profile_file, "line")
    elif geo.bed_profile is not None:
        points = np.asarray(geo.bed_profile, dtype=float)
    else:
        return None
    if len(points) < 2:
        raise GeometryError(f"{key}: {len(points)} point(s); the bed needs at least two")
    dx = np.diff(points[:, 0])
    if np.any(dx <= 0):
        i = int(np.argmax(dx <= 0)) + 1
        raise GeometryError(
            f"{key} is not a function of x: point {i + 1} (x = {points[i, 0]:g}) does not "
            f"come after point {i} (x = {points[i - 1, 0]:g}); the bed is z_b(x), with x "
            "increasing along it")
    return BedProfile(points)


def mass_ring(geo: Any) -> np.ndarray | None:
    """The user's mass polygon (counter-clockwise, without the closing point), checked to
    be closed and simple; None if the mass is a built-in shape."""
    if geo.mass is not None and geo.mass_file is not None:
        raise GeometryError("geometry.mass and geometry.mass_file both give the mass; set "
                            "one of them")
    if geo.mass_file is not None:
        key, points = "geometry.mass_file", _read("geometry.mass_file", geo.mass_file,
                                                  "polygon")
    elif geo.mass is not None:
        key, points = "geometry.mass", np.asarray(geo.mass, dtype=float)
    else:
        return None
    if len(points) < 2 or not np.array_equal(points[0], points[-1]):
        raise GeometryError(
            f"{key} is an open polygon: its last point {_pt(points[-1])} must repeat its "
            f"first {_pt(points[0])}")
    ring = points[:-1]
    ring = ring[np.r_[True, np.any(np.diff(ring, axis=0) != 0, axis=1)]]
    if len(ring) < 3:
        raise GeometryError(f"{key} has {len(ring)} distinct point(s); a polygon needs 3")
    polygon = shapely.Polygon(ring)
    if not polygon.is_valid:
        reason = shapely.is_valid_reason(polygon)
        where = re.match(r"(.*)\[(\S+) (\S+)\]", reason)
        if where:
            reason = f"{where[1]} at ({float(where[2]):g}, {float(where[3]):g})"
        raise GeometryError(f"{key} is not a simple polygon: {reason.lower()} (its edges "
                            "must not cross or touch)")
    if polygon.area <= 0:
        raise GeometryError(f"{key} encloses no area")
    if not polygon.exterior.is_ccw:
        ring = ring[::-1]
    return ring


def build_scene(geo: Any, gate: Any, layer_end: float | None = None,
                interface: bool = False) -> Scene:
    """The scene of a column configuration (``geometry`` and ``gate`` sections).

    ``layer_end``: where the meshed erodible layer ends (arc length along the bed; default
    geometry.bed_length); ``interface``: the layer's top under the column as an interior
    line of the polygon (two materials; the built-in shapes on the level bed only)."""
    profile = bed_profile(geo)
    ring = mass_ring(geo)
    default = profile is None
    bed = profile if profile is not None else BedProfile.flat(0.0, 1.0)
    if geo.axisymmetric and not default:
        _axisymmetric_bed(bed, geo)
    wall = _wall(bed) if geo.left_wall else None
    he = geo.erodible_thickness
    if he > 0 and wall is None:
        raise GeometryError("geometry.erodible_thickness > 0 needs geometry.left_wall = true "
                            "(the layer starts at the wall)")
    if gate.enabled and he > 0:
        raise GeometryError("gate.enabled = true needs a rigid bed "
                            "(geometry.erodible_thickness = 0)")
    end = geo.bed_length if layer_end is None else layer_end
    first = float(bed.arc_length(bed.points[1, 0])[0])
    if ring is None and (default or he <= 0 or end <= first):
        return _builtin_scene(geo, gate, bed, wall, end, interface, default)
    key = "geometry.mass" if geo.mass_file is None else "geometry.mass_file"
    if ring is None:
        ring, key = _builtin_on_profile(geo, bed), "geometry.width"
    scale = max(float(np.ptp(np.vstack([ring, bed.points]), axis=0).max()), 1e-12)
    ring = _on_bed(ring, bed, scale)
    _check_mass(ring, bed, wall, key, scale)
    points, labels = _labelled(ring, bed, wall, None, scale)
    if BED not in labels:
        raise GeometryError(f"{key}: no edge of the mass lies on the bed profile (the mass "
                            "must rest on the bed)")
    the_gate = _gate(points, labels, bed, gate, key) if gate.enabled else None
    if the_gate is not None:
        labels = _gate_labels(points, labels, the_gate, scale)
    if he <= 0:
        return Scene(bed, wall, Polygon(_points(points), tuple(labels)), ring,
                     gate=the_gate, default_bed=default)
    return _with_layer(bed, wall, ring, he, geo.bed_length if layer_end is None else layer_end,
                       scale, default)


def _read(key: str, path: str, kind: str) -> np.ndarray:
    try:
        return read_points(path, kind)
    except GeometryError as err:
        raise GeometryError(f"{key}: {err}") from None


def _points(points: np.ndarray) -> tuple[tuple[float, float], ...]:
    return tuple((float(x), float(z)) for x, z in points)


def _pt(p: np.ndarray) -> str:
    return f"[{p[0]:g}, {p[1]:g}]"


def _wall(bed: BedProfile) -> Line:
    """The left wall: through the profile's first point, normal to its first segment."""
    start = bed.points[0]
    return Line.through(start, bed.normal(0), start + bed.tangent(0))


def _axisymmetric_bed(bed: BedProfile, geo: Any) -> None:
    if bed.points[0, 0] != 0 or bed.points[0, 1] != bed.points[1, 1] or not geo.left_wall:
        raise GeometryError("geometry.axisymmetric = true with a bed profile needs the "
                            "profile to start at x = 0 with a level first segment (its "
                            "normal there is the symmetry axis) and geometry.left_wall = true")


def _builtin_scene(geo: Any, gate: Any, bed: BedProfile, wall: Line | None,
                   layer_end: float, interface: bool, default: bool) -> Scene:
    """The paper's domains (Figure 6), as ``column`` builds them: on the level bed z = 0,
    or in the frame of the profile's first segment (which holds the whole domain)."""
    he = geo.erodible_thickness
    local = column(geo.shape, geo.width, geo.height, geo.front_angle_deg, he,
                   layer_end, interface=interface and he > 0)
    frame = None if default else (bed.points[0], bed.tangent(0), bed.normal(0))
    scene = Scene(bed, wall, local, np.zeros((0, 2)), frame=frame)
    if not default:
        _builtin_on_profile(geo, bed)          # the column's base on the first segment
    mass = scene.to_lab(np.asarray(column(geo.shape, geo.width, geo.height,
                                          geo.front_angle_deg).points))
    points = scene.to_lab(np.asarray(local.points))
    labels = list(local.labels)
    if not geo.left_wall:
        labels = [SURFACE if lab == WALL else lab for lab in labels]
    the_gate = None
    if gate.enabled:
        the_gate = _gate(points, labels, bed, gate, "geometry.shape")
        labels[1] = GATE                     # the front face (bed, face, top, wall)
    end = None
    if he > 0:
        foot = scene.to_lab(np.array([[local.points[1][0], 0.0]]))[0]
        end = Line.through(foot, bed.normal(0), bed.points[0])
    labelled = Polygon(local.points, tuple(labels), local.interior)
    lab = labelled if default else Polygon(_points(points), tuple(labels),
                                           local.interior)
    return Scene(bed, wall, lab, mass, he, layer_end, end, the_gate, default, frame,
                 labelled)


def _builtin_on_profile(geo: Any, bed: BedProfile) -> np.ndarray:
    """The built-in shape in the frame of the profile's first segment, against the wall."""
    first = float(bed.arc_length(bed.points[1, 0])[0])
    if geo.width > first * (1 + 1e-9):
        raise GeometryError(
            f"geometry.width = {geo.width!r} is longer than the bed profile's first segment "
            f"({first:.4g} m): a built-in column stands on that segment; give geometry.mass "
            "for a mass across a slope change")
    local = np.asarray(column(geo.shape, geo.width, geo.height, geo.front_angle_deg).points)
    t, n = bed.tangent(0), bed.normal(0)
    return bed.points[0] + local[:, :1] * t + local[:, 1:] * n


def _on_bed(ring: np.ndarray, bed: BedProfile, scale: float) -> np.ndarray:
    """Points within ON x scale of the bed put on it, and every edge joining two such points
    made to follow the bed (its corners inserted)."""
    height = bed.height(ring)
    near = np.abs(height) <= ON * scale
    ring = np.where(near[:, None], bed.project(ring), ring)
    out: list[np.ndarray] = []
    n = len(ring)
    for i in range(n):
        j = (i + 1) % n
        out.append(ring[i])
        if near[i] and near[j] and ring[j, 0] > ring[i, 0]:
            corners = bed.points[(bed.points[:, 0] > ring[i, 0]) & (bed.points[:, 0] < ring[j, 0])]
            out.extend(corners)
    return np.array(out)


def _check_mass(ring: np.ndarray, bed: BedProfile, wall: Line | None, key: str,
                scale: float) -> None:
    """The mass above the bed, in front of the wall, within the profile."""
    mass = shapely.Polygon(ring)
    far = 10 * scale
    x0, x1 = bed.points[0, 0] - far, bed.points[-1, 0] + far
    top = np.vstack([[x0, bed.z(x0)[0]], bed.points, [x1, bed.z(x1)[0]]])
    bottom = min(float(top[:, 1].min()), float(ring[:, 1].min())) - far
    below = shapely.Polygon(np.vstack([top, [[x1, bottom], [x0, bottom]]]))
    under = shapely.intersection(mass, below)
    if under.area > SAME * mass.area:
        where = under.centroid
        raise GeometryError(
            f"{key}: the mass crosses the bed profile: {under.area:.3g} m2 of it lies below "
            f"z_b(x) (around x = {where.x:.4g}, z = {where.y:.4g})")
    if wall is not None and np.any(wall.height(ring) < -ON * scale):
        worst = ring[np.argmin(wall.height(ring))]
        raise GeometryError(f"{key}: the point {_pt(worst)} lies behind the left wall (the "
                            "wall stands at the bed profile's first point, normal to its "
                            "first segment); set geometry.left_wall = false or move the mass")
    lo, hi = bed.points[0, 0], bed.points[-1, 0]
    if ring[:, 0].min() < lo - ON * scale or ring[:, 0].max() > hi + ON * scale:
        raise GeometryError(f"{key}: the mass reaches x = [{ring[:, 0].min():g}, "
                            f"{ring[:, 0].max():g}], beyond the bed profile's x = [{lo:g}, "
                            f"{hi:g}]; extend the profile")


def _labelled(ring: np.ndarray, bed: BedProfile, wall: Line | None, end: Line | None,
              scale: float) -> tuple[np.ndarray, list[str]]:
    """Each edge's label: on the bed, the wall or the layer's end, else free surface."""
    nxt = np.roll(ring, -1, axis=0)
    mid = 0.5 * (ring + nxt)
    tol = SAME * scale
    labels = []
    for p, q, m in zip(ring, nxt, mid, strict=True):
        pts = np.array([p, q, m])
        if np.all(np.abs(bed.height(pts)) <= tol):
            labels.append(BED)
        elif wall is not None and np.all(np.abs(wall.height(pts)) <= tol):
            labels.append(WALL)
        elif end is not None and np.all(np.abs(end.height(pts)) <= tol):
            labels.append(END)
        else:
            labels.append(SURFACE)
    return ring, labels


def _gate(points: np.ndarray, labels: list[str], bed: BedProfile, gate: Any,
          key: str) -> Gate:
    """The gate on the mass's front face: the edge leaving the bed at the mass's front."""
    if gate.speed > MAX_SPEED:
        raise GeometryError(
            f"gate.speed = {gate.speed!r} m/s is faster than any laboratory gate (at most "
            f"{MAX_SPEED:g} m/s); a gate that fast is an instantaneous release: set "
            "gate.enabled = false")
    n = len(points)
    feet = [i for i in range(n) if labels[i - 1] == BED and labels[i] != BED]
    if not feet:
        raise GeometryError(f"gate.enabled = true: the mass ({key}) has no front face rising "
                            "from the bed")
    i = max(feet, key=lambda k: points[k, 0])
    foot, top = points[i], points[(i + 1) % n]
    face = top - foot
    k = int(bed.segment_of(np.array([foot[0] - 1e-12]))[0])
    cos = float(np.dot(face, -bed.tangent(k)) / np.hypot(*face))   # the mass's angle there
    angle = math.degrees(math.acos(max(-1.0, min(1.0, cos))))
    if not GATE_MIN_DEG <= angle <= 180 - GATE_MIN_DEG:
        raise GeometryError(
            f"gate.enabled = true: the mass's front face ({key}) makes {angle:.3g} degrees "
            f"with the bed; a gate needs a face at least {GATE_MIN_DEG:g} degrees steep "
            "(a rectangle, or a trapezoid's front)")
    inside = points.mean(axis=0)
    line = Line.through(foot, face, inside)
    law = GateLaw(gate.speed_law, gate.speed, gate.tau)
    return Gate(line, float(np.hypot(*face)), law, gate.friction_deg)


def _gate_labels(points: np.ndarray, labels: list[str], gate: Gate,
                 scale: float) -> list[str]:
    """The front face's edges (on the gate's line, from its foot up) labelled ``gate``."""
    out = list(labels)
    n = len(points)
    for i in range(n):
        pts = np.array([points[i], points[(i + 1) % n]])
        if out[i] == SURFACE and np.all(np.abs(gate.line.height(pts)) <= SAME * scale) \
                and np.all(gate.line.along(pts) >= -SAME * scale):
            out[i] = GATE
    return out


def _with_layer(bed: BedProfile, wall: Line | None, ring: np.ndarray, he: float,
                length: float, scale: float, default: bool) -> Scene:
    """The mass on an erodible layer of thickness ``he`` following the bed from the wall to
    arc length ``length``: the union of the two, labelled."""
    mass = shapely.Polygon(ring)
    end_point, k = bed.at_arc_length(length)
    front = float(bed.arc_length(ring[:, 0].max())[0])
    if length <= front:
        raise GeometryError(f"geometry.bed_length = {length!r} must reach beyond the mass "
                            f"(which ends {front:.4g} m along the bed)")
    base = bed.between(0.0, length)
    top = bed.offset(he, 0.0, length)
    strip = shapely.Polygon(np.vstack([base, top[::-1]]))
    if not strip.is_valid:
        raise GeometryError(f"geometry.erodible_thickness = {he!r} is too thick for the "
                            "bed profile's corners (the layer's top folds)")
    union = shapely.union(mass, strip)
    if not isinstance(union, shapely.Polygon) or len(union.interiors):
        raise GeometryError("geometry.mass and the erodible layer do not make one domain "
                            "(the mass must rest on the layer)")
    union = shapely.geometry.polygon.orient(union, 1.0)
    pts = np.asarray(union.exterior.coords)[:-1]
    start = int(np.argmin(np.hypot(*(pts - bed.points[0]).T)))
    pts = np.roll(pts, -start, axis=0)
    end = Line.through(end_point[0], bed.normal(int(k[0])), bed.points[0])
    points, labels = _labelled(pts, bed, wall, end, scale)
    return Scene(bed, wall, Polygon(_points(points), tuple(labels)), ring, he,
                 length, end, None, default)
