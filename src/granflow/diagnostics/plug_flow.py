"""Comparison of the 2D plug flow with the 1D reference solution of (4.1) (section 4)."""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np

from granflow.fem.sampling import point_values


def reference_field(mesh: ngs.Mesh, z: np.ndarray, u: np.ndarray) -> ngs.CoefficientFunction:
    """(U_ref(Z), 0) as a coefficient function: the 1D profile extended in x (section 4);
    in 3D (U_ref(Z), 0, 0), extended in x and y."""
    xyz = mesh.ngmesh.Coordinates()
    if len(xyz) == 0:     # an MPI rank that holds no element (rank 0 in NGSolve's layout)
        xyz = np.array([[0.0] * mesh.dim, [1.0] * mesh.dim])
    low, high = xyz.min(axis=0)[:-1], xyz.max(axis=0)[:-1]     # the box across Z
    across = (1,) * (mesh.dim - 1)
    shape = (len(z), *(2,) * (mesh.dim - 1))     # the voxel table's axes: Z, then Y, X
    table = np.ascontiguousarray(np.broadcast_to(
        np.asarray(u, dtype=float).reshape(len(z), *across), shape))
    start = (*(float(v) for v in low), float(z[0]))
    end = (*(float(v) for v in high), float(z[-1]))
    profile = ngs.VoxelCoefficient(start, end, table, linear=True)
    return ngs.CF((profile, *(0.0,) * (mesh.dim - 1)))


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
