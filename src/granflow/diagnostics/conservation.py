"""Volume (area) of the discrete domain and its drift (Table 2, section 5 acceptance)."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.geometry.mesh import signed_areas


def mesh_area(mesh: ngs.Mesh) -> float:
    """Area of the straight-edged mesh, from the vertex coordinates (exact, cheap)."""
    return float(np.sum(signed_areas(mesh)))


def relative_error(value: float, reference: float) -> float:
    return abs(value - reference) / abs(reference)
