"""What the computed section measures: a plane section (per metre of width) or the r-z
half-plane of an axisymmetric body (the solid of revolution about the axis x = r = 0).

The one place for the volume of revolution: 2 pi times the section's first moment about
the axis (Pappus), for triangles, a polygon given by its boundary, a region and the points
that stand for parts of it; and the names and units the outputs give the amounts (r or x,
m^3 or m^2 per metre, J or J/m). The weak forms take the same weight r from
``fem/measure.py``, whose ``Coordinates`` is a ``Section``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

TWO_PI = 2.0 * math.pi


def polygon_area(xy: np.ndarray, segments: np.ndarray) -> float:
    """Area enclosed by the oriented boundary segments (shoelace)."""
    p, q = xy[segments[:, 0]], xy[segments[:, 1]]
    return float(0.5 * np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]))


def area_gradient(xy: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """d(area)/d(vertex position): half the sum of the outward normals x lengths around it."""
    p, q = xy[segments[:, 0]], xy[segments[:, 1]]
    d = q - p
    normal_len = np.column_stack([d[:, 1], -d[:, 0]])   # outward for a counter-clockwise loop
    grad = np.zeros_like(xy)
    np.add.at(grad, segments[:, 0], 0.5 * normal_len)
    np.add.at(grad, segments[:, 1], 0.5 * normal_len)
    return grad


def revolved_volume(xy: np.ndarray, segments: np.ndarray) -> float:
    """Volume of the solid swept by the polygon turning about the axis x = 0: 2 pi times
    its first moment, int x dA = sum (x_p + x_q)(x_p z_q - x_q z_p) / 6 over the edges."""
    p, q = xy[segments[:, 0]], xy[segments[:, 1]]
    cross = p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]
    return float(TWO_PI * np.sum((p[:, 0] + q[:, 0]) * cross) / 6.0)


def revolved_volume_gradient(xy: np.ndarray, segments: np.ndarray) -> np.ndarray:
    """d(revolved volume)/d(vertex position), edge by edge from ``revolved_volume``."""
    i, j = segments[:, 0], segments[:, 1]
    (xp, zp), (xq, zq) = xy[i].T, xy[j].T
    cross, s = xp * zq - xq * zp, xp + xq
    c = TWO_PI / 6.0
    grad = np.zeros_like(xy)
    np.add.at(grad, i, c * np.column_stack([cross + s * zq, -s * xq]))
    np.add.at(grad, j, c * np.column_stack([cross - s * zp, s * xp]))
    return grad


@dataclass(frozen=True)
class Section:
    """Plane strain (``axisymmetric=False``): amounts are areas of the section, per metre
    of width; axisymmetric: volumes of the solid of revolution (what an incompressible
    axisymmetric flow conserves, not the section's area); ``dimension = 3``: the body
    itself, volumes in m^3 (the section's amounts below refuse it)."""

    axisymmetric: bool = False
    dimension: int = 2

    @property
    def volumetric(self) -> bool:
        """Whether amounts are volumes (of revolution, or of a 3D body), not areas."""
        return self.axisymmetric or self.dimension == 3

    # --- names and units of the outputs ------------------------------------------------
    @property
    def coordinate(self) -> str:
        """The horizontal coordinate's name: r, the distance from the axis, or x."""
        return "r" if self.axisymmetric else "x"

    @property
    def amount(self) -> str:
        """What is conserved and reported: "volume" (of revolution) or "area"."""
        return "volume" if self.volumetric else "area"

    @property
    def unit(self) -> str:
        """The amount's unit in summary.json member names: m3, or m2 per metre."""
        return "m3" if self.volumetric else "m2"

    @property
    def amount_label(self) -> str:
        """The amount's unit for an axis label."""
        return "m^3" if self.volumetric else "m^2 per m"

    @property
    def energy_unit(self) -> str:
        """Kinetic energy of the whole body (J) or per metre of width (J/m)."""
        return "J" if self.volumetric else "J/m"

    @property
    def note(self) -> str:
        """Words for a figure's title ("" in plane strain)."""
        return " (axisymmetric: r from the axis)" if self.axisymmetric else ""

    # --- amounts -------------------------------------------------------------------------
    def _section_only(self) -> None:
        """The amounts below measure a 2D section; a 3D body's are its tetrahedra's."""
        if self.dimension != 2:
            raise ValueError("a section's amount asked of a 3D body (dimension = 3)")

    def triangles(self, areas: np.ndarray, centroid_r: np.ndarray) -> float:
        """The amount of straight-edged triangles of the given areas: their area, or
        2 pi sum(area x centroid radius), exact for triangles (Pappus)."""
        self._section_only()
        if not self.axisymmetric:
            return float(np.sum(areas))
        return float(TWO_PI * np.sum(areas * centroid_r))

    def region(self, shape: Any) -> float:
        """The amount of a region of the section (a shapely geometry): its area, or
        2 pi A r_centroid (Pappus)."""
        self._section_only()
        if not self.axisymmetric:
            return float(shape.area)
        return 0.0 if shape.is_empty else TWO_PI * shape.area * shape.centroid.x

    def weights(self, r: np.ndarray, area: float) -> np.ndarray:
        """The amount each point at distance ``r`` from the axis stands for when it
        represents ``area`` of the section: the area, or the ring 2 pi r area."""
        self._section_only()
        if not self.axisymmetric:
            return np.full(len(r), area)
        return TWO_PI * r * area

    def polygon(self, xy: np.ndarray, segments: np.ndarray) -> float:
        """The amount enclosed by the oriented boundary segments."""
        self._section_only()
        return revolved_volume(xy, segments) if self.axisymmetric else polygon_area(xy, segments)

    def polygon_gradient(self, xy: np.ndarray, segments: np.ndarray) -> np.ndarray:
        """d(``polygon``)/d(vertex position)."""
        self._section_only()
        if self.axisymmetric:
            return revolved_volume_gradient(xy, segments)
        return area_gradient(xy, segments)


PLANE_SECTION = Section(axisymmetric=False)
REVOLVED_SECTION = Section(axisymmetric=True)
