"""VTU snapshots and their PVD index for ParaView (``fields/``): written and read with
meshio; ``read_snapshot`` is the reader of what ``VtkSeries`` writes.

The reader treats the files as untrusted (``io/untrusted.py``, ``io/vtu_check.py``): the
index may only name snapshot files of its own folder, an XML file with a DTD is refused,
a VTU is checked before meshio reads it, and whatever meshio raises (or its ``sys.exit``
on a file it cannot read) becomes one ``RunDirError``.
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np
from meshio import vtu

from granflow.config.messages import fmt_value
from granflow.io.run_dir import RunDirError, atomic_file, atomic_write_text
from granflow.io.untrusted import MB, parse_xml, read_bytes
from granflow.io.vtu_check import VTU_LIMIT, check_vtu

FOLDER = "fields"
INDEX = "fields.pvd"
INDEX_LIMIT = 16 * MB
_SNAPSHOT = re.compile(r"[A-Za-z0-9_-]{1,100}\.vtu")   # a file of fields/ itself


class VtkSeries:
    """A folder of ``fields_NNNNN.vtu`` files and ``fields.pvd`` listing them with times."""

    def __init__(self, folder: Path, place: Callable[[str], Path] | None = None) -> None:
        self.folder = folder
        self.place = place or (lambda name: folder / name)   # where a file of it goes
        self.entries: list[tuple[float, str]] = []

    def write(self, t: float, points: np.ndarray, triangles: np.ndarray,
              point_data: dict[str, np.ndarray], cell_data: dict[str, np.ndarray]) -> Path:
        """A snapshot of a section's triangles (points (n, 2)) or, in 3D, of tetrahedra
        (``triangles`` (m, 4), points (n, 3))."""
        self.folder.mkdir(parents=True, exist_ok=True)
        name = f"fields_{len(self.entries):05d}.vtu"
        pts = points if points.shape[1] == 3 else np.column_stack([points,
                                                                   np.zeros(len(points))])
        pdata = {k: _as_3d(v) for k, v in point_data.items()}
        kind = "tetra" if triangles.shape[1] == 4 else "triangle"
        mesh = meshio.Mesh(pts, [(kind, triangles)], point_data=pdata,
                           cell_data={k: [np.asarray(v)] for k, v in cell_data.items()})
        with atomic_file(self.place(name)) as tmp:
            meshio.write(tmp, mesh, file_format="vtu")
        self.entries.append((t, name))
        self._write_index()
        return self.folder / name

    def _write_index(self) -> None:
        rows = "\n".join(f'    <DataSet timestep="{t:.9g}" file={quoteattr(f)}/>'
                         for t, f in self.entries)
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")
        atomic_write_text(self.place(INDEX), text)


def _as_3d(values: np.ndarray) -> np.ndarray:
    """meshio/ParaView expect 3-component vectors."""
    v = np.asarray(values, dtype=float)
    if v.ndim == 2 and v.shape[1] == 2:
        return np.column_stack([v, np.zeros(len(v))])
    return v


@dataclass(frozen=True)
class Fields:
    """The finite-element fields of one VTU snapshot, at the mesh vertices and cells."""

    t: float
    points: np.ndarray                       # (n, 2) vertex coordinates, m
    triangles: np.ndarray                    # (m, 3) vertex indices
    point_data: dict[str, np.ndarray]        # e.g. velocity (n, 2), pressure (n,)
    cell_data: dict[str, np.ndarray]

    def __repr__(self) -> str:
        def names(data: dict[str, np.ndarray]) -> str:
            return ", ".join(data) or "none"

        return (f"Fields(t = {self.t:g} s, {len(self.points)} points, {len(self.triangles)} "
                f"triangles; point data: {names(self.point_data)}; cell data: "
                f"{names(self.cell_data)})")

    def __getitem__(self, name: str) -> np.ndarray:
        if name in self.point_data:
            return self.point_data[name]
        if name in self.cell_data:
            return self.cell_data[name]
        raise KeyError(f"no field {name!r}; fields: "
                       f"{fmt_value([*self.point_data, *self.cell_data])}")


def snapshots(root: Path) -> list[tuple[float, str]]:
    """(time, file name) of every snapshot of the run in ``root``, from fields.pvd."""
    index = Path(root, FOLDER, INDEX)
    if not os.path.lexists(index):
        return []
    found = []
    for entry in parse_xml(read_bytes(index, INDEX_LIMIT), index).iter("DataSet"):
        name, time = entry.get("file"), entry.get("timestep", "nan")
        if not name:
            continue
        if not _SNAPSHOT.fullmatch(name):
            raise RunDirError(f"'{index}' names {name[:80]!r}, which is not a snapshot file "
                              f"of {FOLDER}/; refused")
        try:
            t = float(time)
        except ValueError:
            t = math.nan
        if not math.isfinite(t):
            raise RunDirError(f"'{index}': the snapshot {name} has no valid time "
                              f"({time[:40]!r})")
        found.append((t, name))
    return found


def read_snapshot(root: Path, t: float) -> Fields:
    """The snapshot at time ``t`` (the nearest one within 1e-6 s)."""
    found = snapshots(root)
    if not found:
        raise RunDirError(f"'{root}' holds no field snapshots ({FOLDER}/{INDEX})")
    nearest, name = min(found, key=lambda item: abs(item[0] - t))
    if not abs(nearest - t) <= 1e-6:
        raise ValueError(f"no snapshot at t = {t:g} s; snapshots at "
                         f"{fmt_value([float(f'{s:g}') for s, _ in found])} s")
    path = Path(root, FOLDER, name)
    data = read_bytes(path, VTU_LIMIT)
    check_vtu(data, path)
    try:   # meshio reads files by name: the checked bytes, from a private copy
        with tempfile.TemporaryDirectory() as folder:
            copy = Path(folder, "snapshot.vtu")
            copy.write_bytes(data)
            mesh = vtu.read(str(copy))    # the reader itself: meshio.read prints and exits
    except (Exception, SystemExit) as err:   # meshio exits on a file it cannot read
        detail = str(err)[:200] or "not a VTU file meshio can read"
        raise RunDirError(f"cannot read the snapshot '{path}': {type(err).__name__}: "
                          f"{detail}") from None
    return _fields(mesh, nearest, path)


def _fields(mesh: meshio.Mesh, t: float, path: Path) -> Fields:
    """The snapshot's arrays, checked against each other: finite points, triangles that
    index them, one value per point or per triangle."""
    points = np.asarray(mesh.points, dtype=float)
    blocks = [c.data for c in mesh.cells if c.type == "triangle"]
    if points.ndim != 2 or points.shape[1] < 2 or len(blocks) != 1:
        raise RunDirError(f"'{path}' does not hold one triangle mesh")
    triangles = np.asarray(blocks[0])
    n, m = len(points), len(triangles)
    if (not np.isfinite(points).all() or triangles.ndim != 2 or triangles.shape[1] != 3
            or triangles.dtype.kind not in "iu"
            or (m and (triangles.min() < 0 or triangles.max() >= n))):
        raise RunDirError(f"'{path}': its points or triangles are invalid")
    point_data = {k: _planar(np.asarray(v)) for k, v in mesh.point_data.items()}
    cell_data = {k: np.asarray(v[0]) for k, v in mesh.cell_data.items() if len(v) == 1}
    for name, values in [*point_data.items(), *cell_data.items()]:
        if len(values) != (n if name in point_data else m):
            raise RunDirError(f"'{path}': the field {name!r} has {len(values)} values for "
                              f"{n} points and {m} triangles")
    return Fields(t=t, points=points[:, :2], triangles=triangles, point_data=point_data,
                  cell_data=cell_data)


def _planar(values: np.ndarray) -> np.ndarray:
    """Vectors written as 3D for ParaView back to their two in-plane components."""
    if values.ndim == 2 and values.shape[1] == 3 and not np.any(values[:, 2]):
        return values[:, :2]
    return values
