"""Volume (area, or volume of revolution) of the discrete domain and its drift (Table 2,
section 5 acceptance)."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.fem.sampling import triangles
from granflow.geometry.mesh import signed_areas
from granflow.geometry.mesh3d import signed_volumes
from granflow.geometry.section import Section


def mesh_area(mesh: ngs.Mesh) -> float:
    """Area of the straight-edged mesh, from the vertex coordinates (exact, cheap)."""
    return float(np.sum(signed_areas(mesh)))


def mesh_volume(mesh: ngs.Mesh, axisymmetric: bool, dimension: int = 2) -> float:
    """The body's volume: the area (m^2 per metre of width) in plane strain; in axisymmetry
    the volume of revolution 2 pi sum(area x centroid radius) (m^3), exact for straight
    triangles (Pappus); in 3D the tetrahedra's (m^3)."""
    if dimension == 3:
        return float(np.sum(signed_volumes(mesh)))
    if not axisymmetric:
        return mesh_area(mesh)
    xy = mesh.ngmesh.Coordinates()
    centroid_r = xy[triangles(mesh), 0].mean(axis=1)
    return Section(axisymmetric=True).triangles(signed_areas(mesh), centroid_r)


def relative_error(value: float, reference: float) -> float:
    return abs(value - reference) / abs(reference)
