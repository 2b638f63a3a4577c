"""Comparison of the 2D plug flow with the 1D reference solution of (4.1) (section 4)."""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np

from granflow.fem.sampling import point_values


def reference_field(mesh: ngs.Mesh, z: np.ndarray, u: np.ndarray) -> ngs.CoefficientFunction:
    """(U_ref(Z), 0) as a coefficient function: the 1D profile extended in x (section 4)."""
    x0, x1 = float(np.min(mesh.ngmesh.Coordinates()[:, 0])), float(
        np.max(mesh.ngmesh.Coordinates()[:, 0]))
    table = np.ascontiguousarray(np.tile(np.asarray(u, dtype=float)[:, None], (1, 2)))
    profile = ngs.VoxelCoefficient((x0, float(z[0])), (x1, float(z[-1])), table, linear=True)
    return ngs.CF((profile, 0.0))


def velocity_errors_l2(mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                       z: np.ndarray, u: np.ndarray) -> tuple[float, float | None]:
    """(||u_h - (U_ref, 0)||_L2, that over ||U_ref||_L2) over the current domain; the
    relative error is None when the reference is at rest (U_ref = 0: nothing to divide by,
    and the absolute error is the result)."""
    ref = reference_field(mesh, z, u)
    diff = velocity - ref
    err2 = ngs.Integrate(diff * diff, mesh, order=8)
    norm2 = ngs.Integrate(ref * ref, mesh, order=8)
    absolute = math.sqrt(max(err2, 0.0))
    return absolute, (absolute / math.sqrt(norm2) if norm2 > 0 else None)


def vertical_profile(mesh: ngs.Mesh, velocity: ngs.CoefficientFunction, x: float,
                     z: np.ndarray) -> np.ndarray:
    """(len(z), 2) velocity samples along the vertical X = x."""
    return point_values(mesh, velocity, x, z)[1]
