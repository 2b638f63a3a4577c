"""Scalar measures of the accepted state, one row of ``diagnostics.csv`` per step."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.diagnostics.conservation import mesh_volume
from granflow.fem.measure import PLANE, Coordinates
from granflow.fem.sampling import cell_means
from granflow.simulation.rest import FLOWING_SPEED


def flowing_cells(mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                  threshold: float = FLOWING_SPEED) -> tuple[np.ndarray, np.ndarray]:
    """Boolean flag per triangle (mean |u| > threshold) and the triangle areas."""
    speed, areas = cell_means(mesh, ngs.Norm(velocity))
    return speed > threshold, areas


def state_measures(mesh: ngs.Mesh, velocity: ngs.CoefficientFunction,
                   density: float | ngs.CoefficientFunction,
                   cell_speed: tuple[np.ndarray, np.ndarray] | None = None,
                   coords: Coordinates = PLANE) -> dict[str, float]:
    """volume, kinetic_energy, max_speed (max cell-mean |u|), flowing_fraction (by area of
    the section). Volume and energy per metre of width in plane strain (m^2, J/m), of the
    whole body in axisymmetry and in 3D (m^3, J).

    ``cell_speed`` = (mean |u| per cell, cell areas) when the caller already has them.
    """
    speed, areas = cell_speed if cell_speed is not None else cell_means(mesh, ngs.Norm(velocity))
    if isinstance(density, ngs.CoefficientFunction):   # a layer of its own material
        energy = 0.5 * coords.integrate(density * velocity * velocity, mesh, order=4)
    else:
        energy = 0.5 * density * coords.integrate(velocity * velocity, mesh, order=4)
    flowing = speed > FLOWING_SPEED
    return {
        "volume": mesh_volume(mesh, coords.axisymmetric, coords.dimension),
        "kinetic_energy": float(energy),
        "max_speed": float(speed.max()),
        "flowing_fraction": float(areas[flowing].sum() / areas.sum()),
    }
