"""Cells stretched along a thin erodible layer, made by meshing in a stretched coordinate.

A layer a few millimetres thick under a column tens of centimetres wide needs a few cells
across it but not along it: the flow in it varies over the column's scales in x. Netgen
meshes isotropically, so the domain is meshed in coordinates where the layer is ``aspect``
times thicker, z' = aspect z below the layer's top h_e and z' = z + (aspect - 1) h_e above,
and the vertices are mapped back. Triangles of the layer come out ``aspect`` times longer
along the bed than across it, and grade above it to the column's size as Netgen grades the
isotropic mesh. Measured in the same coordinates (``quality_coordinates``), a fresh stretched
triangle has the quality of an isotropic one, which is what the remeshing thresholds read.
``aspect = 1`` is the identity: isotropic cells.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SAME = 1e-6     # relative: a vertex this close to the layer's top is on it
SHORTEST = 0.05  # a crossing closer to an end of its edge (relative) is not split there


@dataclass(frozen=True)
class LayerStretch:
    """The map between physical (x, z) and meshing coordinates (x, z') of a layer ``top``
    thick on the bed z = 0, stretched by ``aspect`` >= 1."""

    top: float
    aspect: float = 1.0

    @property
    def identity(self) -> bool:
        return self.aspect == 1.0 or self.top <= 0

    def forward(self, xy: np.ndarray) -> np.ndarray:
        """Physical -> meshing coordinates (a copy; ``xy`` is (n, 2))."""
        out = np.array(xy, dtype=float, copy=True)
        if self.identity:
            return out
        z = out[:, 1]
        out[:, 1] = np.where(z < self.top, self.aspect * z, z + (self.aspect - 1) * self.top)
        return out

    def inverse(self, xy: np.ndarray) -> np.ndarray:
        """Meshing -> physical coordinates (a copy)."""
        out = np.array(xy, dtype=float, copy=True)
        if self.identity:
            return out
        z = out[:, 1]
        top = self.aspect * self.top
        out[:, 1] = np.where(z < top, z / self.aspect, z - (self.aspect - 1) * self.top)
        return out

    def split(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The closed polygon ``points`` with a vertex added where an edge crosses the
        layer's top, and for each vertex the index of the edge it lies on: so every edge
        lies on one side and the map keeps it straight (the boundary, and the area, are
        the same in both coordinates). A crossing within SHORTEST of an end of its edge
        is left: the piece it would cut off would be a sliver Netgen cannot mesh, and the
        part of the edge beyond the top is too short for the map to bend it measurably."""
        pts = np.asarray(points, dtype=float).reshape(-1, 2)
        if self.identity:
            return pts.copy(), np.arange(len(pts))
        side = np.sign(pts[:, 1] - self.top)
        side[np.abs(pts[:, 1] - self.top) <= SAME * self.top] = 0   # on the top
        out, edge = [], []
        for i, p in enumerate(pts):
            j = (i + 1) % len(pts)
            out.append(p)
            edge.append(i)
            if side[i] * side[j] < 0:
                q = pts[j]
                s = (self.top - p[1]) / (q[1] - p[1])
                if SHORTEST < s < 1 - SHORTEST:
                    out.append((p[0] + s * (q[0] - p[0]), self.top))
                    edge.append(i)
        return np.array(out), np.array(edge)

    def length(self, size: float) -> float:
        """The meshing-coordinate edge length of cells ``size`` thick across the layer."""
        return self.aspect * size


ISOTROPIC = LayerStretch(top=0.0)
