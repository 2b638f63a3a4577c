"""What a VTU snapshot holds of the flow (``io/fields.py`` writes it, reading the flow through
its ``FlowFields`` protocol): the mesh's vertices and triangles (tetrahedra in 3D); point
data velocity (m/s) and pressure (Pa); cell data, the means over each cell: speed (m/s),
the flowing flag (speed above 1 mm/s), strain_rate_norm (1/s), effective_viscosity
(Pa s), the stress stress_xx, stress_zz, stress_xz (and stress_hoop for a cylinder; all
six components in 3D) and deviatoric_stress_norm (Pa), and yield_ratio
(``diagnostics/stress.py``)."""

from __future__ import annotations

from typing import Protocol

import ngsolve as ngs

from granflow.diagnostics.stress import static_yield_stress, stress_components, yield_ratio
from granflow.fem.flow import FlowSolver
from granflow.fem.sampling import cell_means, cells, vertex_samples
from granflow.io.fields import Snapshot
from granflow.simulation.rest import FLOWING_SPEED


class Host(Protocol):
    """Where the current mesh and flow live (a remesh replaces both)."""

    mesh: ngs.Mesh
    solver: FlowSolver


class FlowSnapshot:
    """The snapshot of ``host``'s current flow (``io/fields.py: FlowFields``)."""

    def __init__(self, host: Host) -> None:
        self.host = host

    def snapshot(self) -> Snapshot:
        solver, mesh = self.host.solver, self.host.mesh
        speed, _ = cell_means(mesh, ngs.Norm(solver.velocity))
        stress = {name: cell_means(mesh, cf)[0]
                  for name, cf in stress_components(solver).items()}
        kappa = cell_means(mesh, static_yield_stress(solver.rheology, solver.pressure))[0]
        stress["yield_ratio"] = yield_ratio(stress["deviatoric_stress_norm"], kappa)
        return Snapshot(
            mesh.ngmesh.Coordinates().copy(), cells(mesh),
            point_data={"velocity": vertex_samples(mesh, solver.velocity),
                        "pressure": vertex_samples(mesh, solver.pressure)},
            cell_data={"flowing": (speed > FLOWING_SPEED).astype(float), "speed": speed,
                       "strain_rate_norm": cell_means(mesh, solver.strain_rate_norm())[0],
                       "effective_viscosity":
                           cell_means(mesh, solver.effective_viscosity())[0],
                       **stress})
