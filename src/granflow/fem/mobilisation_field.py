"""The mobilisation state of a hysteretic friction (``physics/hysteresis.py``) on the moving
mesh: one value per triangle, carried with the material and relaxed after each accepted
step (a remesh carries it over with ``ale/transfer.transfer_cells``).

Transport. Between relaxations the state moves with the material, Ds/Dt = 0; in the frame
of the mesh, which moves with the mesh velocity w, ds/dt + (u - w) . grad s = 0. The cell
values are advanced by the upwind (DG0, finite-volume) step

    s_K <- s_K + dt / |K| sum_{edges e of K} int_e [-(u - w) . n_K]_+ (s_e - s_K),

s_e the neighbour's value across e, the cell's own on the boundary (the flow does not cross
the free surface, the bed or the walls: (u - w) . n is only the penalty's residual there).
Each new value is a convex combination of old ones while dt max_K(in-flux / |K|) <= 1, so s
stays in [0, 1]; the step is cut into as many substeps as that takes. w is the mesh's
actual motion over the step (the vertex displacement over dt, linear on each triangle:
(3.6) with the deposition's snaps and the area fix). First order in space and time, like
the mesh's own move (3.1).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import ngsolve as ngs
import numpy as np
from scipy import sparse

from granflow.fem.coupling import Coupling, Site
from granflow.fem.sampling import cell_means
from granflow.physics.hysteresis import Relaxation


class MobilisationField:
    """s per triangle of ``mesh`` (an L2 field of order 0), read by the law as ``cf``."""

    def __init__(self, mesh: ngs.Mesh) -> None:
        self.mesh = mesh
        self.space = ngs.L2(mesh, order=0, dgjumps=True)
        self.state = ngs.GridFunction(self.space)
        # the law reads it as it is; on a wall from the adjacent triangle (a plain L2
        # function is 0 on a boundary element): ``fem/engine.py: read_on_walls``
        self.cf = self.state
        self._mesh_velocity = ngs.GridFunction(ngs.VectorH1(mesh, order=1))

    @property
    def values(self) -> np.ndarray:
        """The cell values, a writable view."""
        return self.state.vec.FV().NumPy()

    def advect(self, velocity: ngs.CoefficientFunction, displacement: np.ndarray,
               dt: float) -> int:
        """Carry s over a step of length dt in which the material moved with ``velocity``
        and the mesh's vertices by ``displacement`` (nv, 2) (module docstring); returns the
        number of substeps."""
        if dt <= 0:
            return 0
        nv = self.mesh.nv
        for c, component in enumerate(self._mesh_velocity.components):
            component.vec.FV().NumPy()[:nv] = displacement[:, c] / dt
        relative = velocity - self._mesh_velocity
        flux = relative * ngs.specialcf.normal(2)
        s, v = self.space.TnT()
        inward = ngs.IfPos(flux, 0.0, flux)      # -[-(u - w).n]_+
        inflow = ngs.BilinearForm(self.space)    # its diagonal: the in-flux of each cell
        inflow += (inward * (s.Other() - s) * v).Compile() * ngs.dx(element_boundary=True)
        # on the boundary Other() is 0 in an assembled form: there the neighbour is the
        # cell itself, nothing enters
        inflow += (inward * s * v).Compile() * ngs.ds(skeleton=True)
        inflow.Assemble()
        data, columns, rows = inflow.mat.CSR()
        n = len(self.values)
        operator = sparse.csr_matrix((np.array(data), np.array(columns), np.array(rows)),
                                     shape=(n, n))
        areas = ngs.Integrate(ngs.CF(1.0), self.mesh, element_wise=True).NumPy()
        operator = sparse.diags(-1.0 / areas) @ operator     # ds/dt = operator s
        rate = float(np.max(-operator.diagonal(), initial=0.0))   # in-flux / |K|
        substeps = max(1, math.ceil(dt * rate))
        h = dt / substeps
        values = self.values
        for _ in range(substeps):
            values += h * (operator @ values)
        np.clip(values, 0.0, 1.0, out=values)      # round-off of the convex combinations
        return substeps

    def shear_rates(self, strain_rate_norm: ngs.CoefficientFunction) -> np.ndarray:
        """gamma_dot = sqrt(2) |Du| per triangle (cell means), what the relaxation reads."""
        return math.sqrt(2.0) * cell_means(self.mesh, strain_rate_norm)[0]

    def relax(self, relaxation: Relaxation, shear_rate: np.ndarray, dt: float) -> None:
        """s after dt of relaxation at the given shear rates (``Relaxation.relax``)."""
        self.values[:] = relaxation.relax(self.values, shear_rate, dt)


@dataclass(frozen=True)
class MobilisationSpec:
    """A hysteretic friction's state on each mesh of a run."""

    def build(self, site: Site, fields: Mapping[str, Any]) -> MobilisationCoupling:
        return MobilisationCoupling(MobilisationField(site.mesh))


class MobilisationCoupling(Coupling):
    """The mobilisation s the hysteretic law reads (its field and its cell values). It is
    advanced, carried through a remesh and checkpointed by the run's callback
    (``scenarios/mobilisation_tracking.py``), after each accepted step."""

    name = "mobilisation"

    def __init__(self, field: MobilisationField) -> None:
        self.field = field

    def law_fields(self) -> Mapping[str, Any]:
        return {"mobilisation": self.field.cf, "per_triangle": self.field.state}
