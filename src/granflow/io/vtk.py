"""VTU snapshots and their PVD index for ParaView (``fields/``): written and read with
meshio; ``read_snapshot`` is the reader of what ``VtkSeries`` writes."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np

from granflow.io.run_dir import RunDirError

FOLDER = "fields"
INDEX = "fields.pvd"


class VtkSeries:
    """A folder of ``fields_NNNNN.vtu`` files and ``fields.pvd`` listing them with times."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.entries: list[tuple[float, str]] = []

    def write(self, t: float, points: np.ndarray, triangles: np.ndarray,
              point_data: dict[str, np.ndarray], cell_data: dict[str, np.ndarray]) -> Path:
        self.folder.mkdir(parents=True, exist_ok=True)
        name = f"fields_{len(self.entries):05d}.vtu"
        pts = np.column_stack([points, np.zeros(len(points))])
        pdata = {k: _as_3d(v) for k, v in point_data.items()}
        mesh = meshio.Mesh(pts, [("triangle", triangles)], point_data=pdata,
                           cell_data={k: [np.asarray(v)] for k, v in cell_data.items()})
        tmp = self.folder / f".{name}.tmp"
        meshio.write(tmp, mesh, file_format="vtu")
        os.replace(tmp, self.folder / name)
        self.entries.append((t, name))
        self._write_index()
        return self.folder / name

    def _write_index(self) -> None:
        rows = "\n".join(f'    <DataSet timestep="{t:.9g}" file={quoteattr(f)}/>'
                         for t, f in self.entries)
        text = ('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n")
        tmp = self.folder / ".fields.pvd.tmp"
        tmp.write_text(text)
        os.replace(tmp, self.folder / INDEX)


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
                       f"{', '.join([*self.point_data, *self.cell_data])}")


def snapshots(root: Path) -> list[tuple[float, str]]:
    """(time, file name) of every snapshot of the run in ``root``, from fields.pvd."""
    index = Path(root, FOLDER, INDEX)
    if not index.is_file():
        return []
    tree = ElementTree.parse(index)
    return [(float(e.get("timestep", "nan")), str(e.get("file")))
            for e in tree.iter("DataSet") if e.get("file")]


def read_snapshot(root: Path, t: float) -> Fields:
    """The snapshot at time ``t`` (the nearest one within 1e-6 s)."""
    found = snapshots(root)
    if not found:
        raise RunDirError(f"'{root}' holds no field snapshots ({FOLDER}/{INDEX})")
    nearest, name = min(found, key=lambda item: abs(item[0] - t))
    if abs(nearest - t) > 1e-6:
        raise ValueError(f"no snapshot at t = {t:g} s; snapshots at "
                         f"{', '.join(f'{s:g}' for s, _ in found)} s")
    mesh = meshio.read(Path(root, FOLDER, name))
    return Fields(t=nearest, points=mesh.points[:, :2], triangles=mesh.cells_dict["triangle"],
                  point_data={k: _planar(v) for k, v in mesh.point_data.items()},
                  cell_data={k: v[0] for k, v in mesh.cell_data.items()})


def _planar(values: np.ndarray) -> np.ndarray:
    """Vectors written as 3D for ParaView back to their two in-plane components."""
    if values.ndim == 2 and values.shape[1] == 3 and not np.any(values[:, 2]):
        return values[:, :2]
    return values
