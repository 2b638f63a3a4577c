"""The discretised collapse on one mesh: the flow solver (3.2) with its Coulomb walls and
the ALE mover (3.6)/(3.7). A remesh builds a new one on the new mesh (``column_remesher``);
the parts that read the current mesh (``column_measures``, the outputs) hold the same
``ColumnDiscretisation`` object and so always see the current one."""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs

from granflow.ale.column_mover import ColumnMover
from granflow.ale.deposition import Support
from granflow.ale.free_surface import polygon_measure
from granflow.ale.mesh_motion import ElasticMeshVelocity, LagrangeMeshVelocity
from granflow.ale.surface_tension import SurfaceTension
from granflow.fem.flow import FlowSolver
from granflow.fem.forms import FrictionWall
from granflow.fem.linalg import direct_solver
from granflow.fem.mobilisation_field import MobilisationField
from granflow.fem.sampling import triangles
from granflow.geometry.layer_material import LayerMaterial
from granflow.geometry.mesh import BED, END, GATE, SURFACE, WALL
from granflow.physics import CoulombFriction, gravity_vector
from granflow.scenarios.bed import bed_wall, rough_bed
from granflow.scenarios.column_setup import ColumnSetup
from granflow.scenarios.fluidity import fluidity_field
from granflow.scenarios.materials import augmentation, build_side_walls


@dataclass
class ColumnDiscretisation:
    """The current mesh and what lives on it."""

    mesh: ngs.Mesh
    solver: FlowSolver
    mover: ColumnMover
    fraction: ngs.GridFunction | None = None   # two materials: layer share per triangle
    mobilisation: MobilisationField | None = None   # a hysteretic friction's state

    def replace(self, other: ColumnDiscretisation) -> None:
        """Take ``other``'s mesh, solver, mover, indicator and mobilisation (after a remesh
        or a restore)."""
        self.mesh, self.solver, self.mover = other.mesh, other.solver, other.mover
        self.fraction, self.mobilisation = other.fraction, other.mobilisation

    def set_fraction(self, layer: LayerMaterial | None) -> None:
        """The material indicator of the current mesh from the tracked layer region."""
        if self.fraction is not None and layer is not None:
            self.fraction.vec.FV().NumPy()[:] = layer.fractions(
                self.mesh.ngmesh.Coordinates(), triangles(self.mesh))


def friction_walls(setup: ColumnSetup) -> list[str]:
    """The boundaries with Coulomb friction and the normal penalty: the bed, the wall at
    x = 0 unless it is the symmetry axis, and the far end of an erodible layer."""
    walls = [BED] if setup.axisymmetric else [BED, WALL]
    walls += [GATE] if setup.scene.gate is not None else []
    return [*walls, END] if setup.erodible else walls


def discretise(setup: ColumnSetup, mesh: ngs.Mesh,
               layer: LayerMaterial | None = None) -> ColumnDiscretisation:
    """The flow solver (3.2) with Coulomb walls and the ALE mover (3.6)/(3.7) on ``mesh``;
    in axisymmetry the left boundary is the axis: u_r = 0 there, no friction, no penalty.
    A layer of its own material (``[layer]``) gets the blended law and density, with the
    indicator filled from the tracked region ``layer``."""
    config, scene, coords = setup.config, setup.scene, setup.coordinates
    geo, mat, bnd, num = config.geometry, config.material, config.boundary, config.numerics
    load = bnd.normal_load
    walls: list[FrictionWall] = []     # the bed's, once the law is built
    if not coords.axisymmetric:
        walls.append(FrictionWall(WALL, CoulombFriction(bnd.wall_friction_deg,
                                                        num.eps_friction), load))
    if setup.erodible:   # the layer's far end: frictionless, u.N = 0 (domains.py)
        walls.append(FrictionWall(END, CoulombFriction(0.0, num.eps_friction), load))
    gate_speed = ngs.Parameter(0.0) if scene.gate is not None else None
    if scene.gate is not None:     # slides up along itself: friction against its motion
        walls.append(FrictionWall(GATE, CoulombFriction(scene.gate.friction_deg,
                                                        num.eps_friction), load,
                                  velocity=gate_speed * ngs.CF(scene.gate.line.direction)))
    st = config.surface_tension
    materials = setup.materials
    mobilisation = MobilisationField(mesh) if materials.hysteretic else None
    fraction = (ngs.GridFunction(ngs.L2(mesh, order=0))
                if materials.layer is not None else None)
    # a plain L2 function is 0 on a boundary element: the walls read the adjacent
    # triangle's (fem/engine.py: read_on_walls), the volume the function itself
    share = fraction
    fluidity = fluidity_field(config, materials, mesh, coords=coords, fraction=share,
                              rough=rough_bed(config))
    state = (mobilisation.cf, mobilisation.state) if mobilisation is not None else (0.0, None)
    side_walls, augmented = build_side_walls(config), augmentation(config)
    rheology, density = materials.law(num.eps, *state, share=share, fluidity=(
        fluidity.current if fluidity is not None else 0.0))
    walls.insert(0, bed_wall(config, rheology))
    solver = FlowSolver(mesh, rheology=rheology, density=density,
                        body_force=gravity_vector(mat.gravity, geo.slope_deg),
                        walls=walls, penalty=bnd.penalty, linearization=num.linearization,
                        linear_solver=direct_solver(num.linear_solver),
                        initial_guess=num.initial_guess,
                        surface_tension_on=SURFACE if st.enabled else None,
                        side_walls=side_walls, augmentation=augmented,
                        scheme=config.time.scheme, coordinates=coords,
                        axis=WALL if coords.axisymmetric else "",
                        anderson_depth=num.anderson_depth, fluidity=fluidity,
                        fluidity_coupling=num.fluidity_coupling)
    tension = (SurfaceTension(solver.surface_tension, st.delta, st.gamma0,
                              st.trigger_angle_deg, config.mesh.size,
                              st.release_angle_deg, st.length) if st.enabled else None)
    velocity_cls = LagrangeMeshVelocity if num.mesh_velocity == "lagrange" else (
        ElasticMeshVelocity)
    source = ngs.GridFunction(solver.space.components[0])
    w_solver = velocity_cls(mesh, source, solver.mesh_velocity, num.mesh_penalty,
                            solver=direct_solver(num.linear_solver))
    mover = ColumnMover(mesh, w_solver,
                        source=source, flow=solver, target=solver.mesh_velocity,
                        extrapolate=num.ale_extrapolation,
                        conserve_volume=num.volume_correction, tension=tension,
                        measure=polygon_measure(coords.axisymmetric),
                        support=Support(scene.bed, scene.wall), gate=scene.gate,
                        gate_speed=gate_speed)
    out = ColumnDiscretisation(mesh, solver, mover, fraction, mobilisation)
    out.set_fraction(layer)
    return out
