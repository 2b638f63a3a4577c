"""The meshes of version-2 checkpoints, stored in Netgen's text format (``.vol``), parsed
strictly into arrays so that Netgen's own reader never sees a file from someone else (an
out-of-range, zero or negative point index, a negative count or a file cut short crashed
it); ``granflow.geometry.mesh.build_mesh`` then rebuilds the mesh from the arrays.

Read: ``surfaceelements`` (triangles), ``edgesegmentsgi3`` (boundary segments and their
boundary index), ``points`` and ``bcnames``; every other section is skipped by its count.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from granflow.geometry.mesh import LABELS

MAX_ITEMS = 10**7      # points, triangles or segments of one mesh
FARTHEST = 1e6         # m from the origin: the configuration's points lie within 1e5 m
_SINGLE = {"dimension", "geomtype"}          # a keyword and one value line


@dataclass(frozen=True)
class MeshArrays:
    """A column mesh as arrays: vertices (n, 2), triangles (m, 3) and boundary segments
    (k, 2) as 0-based vertex indices, and each segment's label (one of ``LABELS``)."""

    points: np.ndarray
    triangles: np.ndarray
    segments: np.ndarray
    labels: list[str]

    def check(self) -> None:
        """Raise ValueError unless the arrays make a mesh ``build_mesh`` can take."""
        n = len(self.points)
        if self.points.dtype != np.float64 or self.points.ndim != 2 or \
                self.points.shape[1] != 2 or n < 3 or n > MAX_ITEMS:
            raise ValueError(f"the mesh's vertices are not (n, 2) floats: {self.points.dtype}, "
                             f"shape {self.points.shape}")
        if not np.isfinite(self.points).all():
            raise ValueError("the mesh has a vertex that is not finite")
        for name, cells, width in (("triangle", self.triangles, 3),
                                   ("boundary segment", self.segments, 2)):
            if cells.ndim != 2 or cells.shape[1] != width or len(cells) > MAX_ITEMS:
                raise ValueError(f"the mesh's {name}s have shape {cells.shape}")
            if cells.dtype.kind not in "iu":
                raise ValueError(f"the mesh's {name}s are not vertex indices")
            if cells.size and (cells.min() < 0 or cells.max() >= n):
                raise ValueError(f"a {name} of the mesh names a vertex outside 0..{n - 1}")
            if len(cells) and (np.sort(cells, axis=1)[:, 1:] == np.sort(cells, axis=1)[:, :-1]
                               ).any():
                raise ValueError(f"a {name} of the mesh repeats a vertex")
        if len(self.triangles) == 0:
            raise ValueError("the mesh has no triangles")
        if len(self.labels) != len(self.segments) or not set(self.labels) <= set(LABELS):
            raise ValueError("the mesh's boundary labels do not match its segments")
        _check_geometry(self.points, self.triangles, self.segments)


def _check_geometry(points: np.ndarray, triangles: np.ndarray, segments: np.ndarray) -> None:
    """Raise ValueError unless the mesh is one a run could have: vertices within
    ``FARTHEST``, every triangle counter-clockwise with a positive area, none twice, no two
    overlapping along an edge (an edge is used at most once in each direction), and the
    labelled segments exactly the edges of one triangle (the boundary, closed)."""
    if np.abs(points).max() > FARTHEST:
        raise ValueError(f"the mesh has a vertex farther than {FARTHEST:g} m from the origin")
    a, b, c = (points[triangles[:, i]] for i in range(3))
    areas = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    if not (areas > 0).all():
        bad = np.flatnonzero(~(areas > 0))
        raise ValueError(f"the mesh has {len(bad)} triangles that are inverted or of no area "
                         f"(triangle {bad[0]} first)")
    if len(np.unique(np.sort(triangles, axis=1), axis=0)) < len(triangles):
        raise ValueError("the mesh holds a triangle twice")
    directed = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    if len(np.unique(directed, axis=0)) < len(directed):
        raise ValueError("two triangles of the mesh overlap (an edge is used twice in the "
                         "same direction)")
    edges, counts = np.unique(np.sort(directed, axis=1), axis=0, return_counts=True)
    boundary = {tuple(edge) for edge in edges[counts == 1].tolist()}
    labelled = [tuple(edge) for edge in np.sort(segments, axis=1).tolist()]
    if len(set(labelled)) < len(labelled):
        raise ValueError("the mesh has a boundary segment twice")
    if set(labelled) != boundary:
        raise ValueError(f"the mesh's labelled segments do not close its domain "
                         f"({len(boundary - set(labelled))} boundary edges without a label, "
                         f"{len(set(labelled) - boundary)} labels off the boundary)")


def parse_vol(text: str) -> MeshArrays:
    """The mesh in Netgen's text format (module docstring); ValueError if it is not one."""
    lines = [line.split() for line in text.splitlines()
             if line.strip() and not line.lstrip().startswith("#")]
    if not lines or lines[0] != ["mesh3d"]:
        raise ValueError("the stored mesh is not in Netgen's .vol format")
    sections: dict[str, list[list[str]]] = {}
    i = 1
    while i < len(lines) and lines[i] != ["endmesh"]:
        keyword = lines[i][0]
        if keyword in _SINGLE:
            i += 2
            continue
        count = _integer(lines[i + 1][0] if i + 1 < len(lines) else "", keyword)
        if not 0 <= count <= MAX_ITEMS or i + 2 + count > len(lines):
            raise ValueError(f"the mesh's section {keyword[:30]!r} has a bad count {count}")
        sections[keyword] = lines[i + 2:i + 2 + count]
        i += 2 + count
    missing = {"surfaceelements", "edgesegmentsgi3", "points", "bcnames"} - set(sections)
    if missing:
        raise ValueError(f"the stored mesh lacks {', '.join(sorted(missing))}")
    names = {_integer(row[0], "bcnames"): row[1] for row in sections["bcnames"]
             if len(row) == 2}
    rows = sections["surfaceelements"]
    if any(len(row) != 8 or row[4] != "3" for row in rows):
        raise ValueError("the stored mesh has an element that is not a triangle")
    triangles = _indices([row[5:8] for row in rows], "surfaceelements", 3)
    rows = sections["edgesegmentsgi3"]
    if any(len(row) != 7 for row in rows):
        raise ValueError("the stored mesh has a malformed boundary segment")
    segments = _indices([row[:2] for row in rows], "edgesegmentsgi3", 2)
    labels = [names.get(_integer(row[6], "edgesegmentsgi3") + 1, "?") for row in rows]
    try:
        points = np.array([[float(v) for v in row[:2]] for row in sections["points"]
                           if len(row) == 3], dtype=float).reshape(-1, 2)
    except ValueError:
        raise ValueError("the stored mesh has a vertex that is not a number") from None
    if len(points) != len(sections["points"]):
        raise ValueError("the stored mesh has a malformed vertex")
    mesh = MeshArrays(points, triangles, segments, labels)
    mesh.check()
    return mesh


def _integer(text: str, where: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise ValueError(f"the mesh's section {where[:30]!r} has {text[:20]!r} where a whole "
                         "number belongs") from None


def _indices(rows: list[list[str]], where: str, width: int) -> np.ndarray:
    """1-based vertex numbers of the file as 0-based indices (range checked later)."""
    return np.array([[_integer(v, where) - 1 for v in row] for row in rows],
                    dtype=np.int64).reshape(-1, width)
