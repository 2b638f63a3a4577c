"""The discretised collapse on one mesh: the flow solver (3.2) with its Coulomb walls and
the ALE mover (3.6)/(3.7). A remesh builds a new one on the new mesh (``column_remesher``);
the parts that read the current mesh (``column_measures``, the outputs) hold the same
``ColumnDiscretisation`` object and so always see the current one."""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from granflow.ale.column_mover import ColumnMover
from granflow.ale.deposition import Support
from granflow.ale.free_surface import polygon_measure
from granflow.ale.mesh_motion import ElasticMeshVelocity, LagrangeMeshVelocity
from granflow.ale.surface_tension import SurfaceTension
from granflow.fem.flow import FlowSolver
from granflow.fem.flow_factory import build_flow
from granflow.fem.mobilisation_field import MobilisationField
from granflow.fem.sampling import triangles
from granflow.geometry.layer_material import LayerMaterial
from granflow.geometry.mesh import BED, END, GATE, WALL
from granflow.scenarios.column_setup import ColumnSetup
from granflow.scenarios.materials import share_of
from granflow.scenarios.mobilisation_tracking import mobilisation_of

SHARE_FIXES = 4   # rounds of the free-surface fix and the share at most (``set_fraction``)


@dataclass
class ColumnDiscretisation:
    """The current mesh and what lives on it."""

    mesh: ngs.Mesh
    solver: FlowSolver
    mover: ColumnMover

    def replace(self, other: ColumnDiscretisation) -> None:
        """Take ``other``'s mesh, solver and mover (after a remesh or a restore)."""
        self.mesh, self.solver, self.mover = other.mesh, other.solver, other.mover

    @property
    def fraction(self) -> ngs.GridFunction | None:
        """Two materials: the share of layer material per triangle (else None)."""
        return share_of(self.solver)

    @property
    def mobilisation(self) -> MobilisationField | None:
        """A hysteretic friction's state (else None)."""
        return mobilisation_of(self.solver)

    def set_fraction(self, layer: LayerMaterial | None, moved: bool = False) -> None:
        """The material indicator of the current mesh from the tracked layer region.
        ``moved``: the layer moved with the accepted step. With a packing fraction the
        share of layer material enters the grains' mass (the two materials' densities
        blended by it, ``fem/packing.py``): the free-surface fix then restores the mass, as
        after the step itself (not on a new or restored mesh: a remesh restores it, a
        checkpoint holds the state after the fix)."""
        if self.fraction is None or layer is None:
            return
        share, xy = self.fraction.vec.FV().NumPy(), self.mesh.ngmesh.Coordinates()
        mover = self.mover
        share[:] = layer.fractions(xy, triangles(self.mesh))
        if not (moved and mover.conserve_volume and mover.excess(xy) != 0.0):
            return
        for _ in range(SHARE_FIXES):    # the fix moves the surface cells, and their share
            mover.conserve_again(xy)
            again = layer.fractions(xy, triangles(self.mesh))
            if np.array_equal(again, share):
                break
            share[:] = again      # the share of the vertices kept (a checkpoint's, too)


def friction_walls(setup: ColumnSetup) -> list[str]:
    """The boundaries with Coulomb friction and the normal penalty: the bed, the wall at
    x = 0 unless it is the symmetry axis, and the far end of an erodible layer."""
    walls = [BED] if setup.axisymmetric else [BED, WALL]
    walls += [GATE] if setup.scene.gate is not None else []
    return [*walls, END] if setup.erodible else walls


def discretise(setup: ColumnSetup, mesh: ngs.Mesh,
               layer: LayerMaterial | None = None) -> ColumnDiscretisation:
    """The flow solver (3.2) of the set-up's frozen parts (``setup.flow``) and the ALE
    mover (3.6)/(3.7) on ``mesh``; a layer of its own material gets its indicator filled
    from the tracked region ``layer``."""
    config, scene = setup.config, setup.scene
    num, st = config.numerics, config.surface_tension
    solver = build_flow(mesh, setup.flow)
    tension = (SurfaceTension(solver.surface_tension, st.delta, st.gamma0,
                              st.trigger_angle_deg, config.mesh.size,
                              st.release_angle_deg, st.length) if st.enabled else None)
    velocity_cls = LagrangeMeshVelocity if num.mesh_velocity == "lagrange" else (
        ElasticMeshVelocity)
    source = ngs.GridFunction(solver.space.components[0])
    w_solver = velocity_cls(mesh, source, solver.mesh_velocity, num.mesh_penalty,
                            solver=setup.flow.solver.linear_solver)
    mover = ColumnMover(mesh, w_solver,
                        source=source, flow=solver, target=solver.mesh_velocity,
                        extrapolate=num.ale_extrapolation,
                        conserve_volume=num.volume_correction, tension=tension,
                        measure=polygon_measure(setup.axisymmetric),
                        support=Support(scene.bed, scene.wall), gate=scene.gate,
                        gate_speed=setup.gate_speed, excess=solver.volume_excess)
    out = ColumnDiscretisation(mesh, solver, mover)
    out.set_fraction(layer)
    return out
