"""VTU snapshots and their PVD index for ParaView, written with meshio."""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import meshio
import numpy as np


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
        os.replace(tmp, self.folder / "fields.pvd")


def _as_3d(values: np.ndarray) -> np.ndarray:
    """meshio/ParaView expect 3-component vectors."""
    v = np.asarray(values, dtype=float)
    if v.ndim == 2 and v.shape[1] == 2:
        return np.column_stack([v, np.zeros(len(v))])
    return v
