"""Built-in initial domains as labelled polygons (paper Figure 6).

Coordinates are (X, Z) in metres with the wall at X = 0 and the rigid bed at Z = 0. Each
polygon edge carries a boundary label: ``bed``, ``wall``, ``surface`` or ``end`` (the far end
of an erodible layer).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from granflow.geometry.labels import BED, END, SURFACE, WALL


@dataclass(frozen=True)
class Polygon:
    """Counter-clockwise vertices and the label of edge i (from vertex i to i+1)."""

    points: tuple[tuple[float, float], ...]
    labels: tuple[str, ...]
    interior: tuple[tuple[int, int], ...] = ()   # lines between two points, inside

    @property
    def area(self) -> float:
        pts = self.points
        return 0.5 * sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1)
                         in zip(pts, pts[1:] + pts[:1], strict=True))

    def surface_height(self, x: float) -> float:
        """Highest Z of the polygon boundary above X = x (for the hydrostatic start)."""
        best = 0.0
        pts = self.points
        for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1], strict=True):
            if min(x0, x1) <= x <= max(x0, x1) and x0 != x1:
                best = max(best, y0 + (y1 - y0) * (x - x0) / (x1 - x0))
        return best


def column(shape: str, width: float, height: float, front_angle_deg: float = 90.0,
           erodible_thickness: float = 0.0, bed_length: float = 1.0,
           interface: bool = False) -> Polygon:
    """Trapezoid (front face at ``front_angle_deg`` from the bed, base ``width``) or rectangle.

    With ``erodible_thickness`` > 0 a layer of that thickness covers the bed up to
    ``bed_length`` (configuration (III)); the column stands on it, its front face continued
    through the layer down to X = ``width`` on the rigid bed (the same base-width
    convention as over a rigid bed), so ``height`` includes the layer. The layer's far end
    is a frictionless wall (label ``end``): a layer at rest under gravity carries no shear
    on vertical planes, so this is the exact boundary of an undisturbed layer that goes on
    beyond ``bed_length``; a free end would slump. With ``interface`` the layer's top under
    the column (from the wall to the front face) is an interior line, so that a mesh of a
    column and a layer of two materials starts with no triangle holding both.
    """
    angle = 90.0 if shape == "rectangle" else front_angle_deg
    top = width - height / math.tan(math.radians(angle)) if angle < 90 else width
    he = erodible_thickness
    if he > 0:
        foot = width - he / math.tan(math.radians(angle)) if angle < 90 else width
        points = ((0.0, 0.0), (bed_length, 0.0), (bed_length, he), (foot, he),
                  (top, height), (0.0, height))
        labels = (BED, END, SURFACE, SURFACE, SURFACE, WALL)
        if interface:
            return Polygon(points=(*points, (0.0, he)), labels=(*labels, WALL),
                           interior=((6, 3),))
    else:
        points = ((0.0, 0.0), (width, 0.0), (top, height), (0.0, height))
        labels = (BED, SURFACE, SURFACE, WALL)
    return Polygon(points=points, labels=labels)
