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
from granflow.ale.remesh import EdgeSize
from granflow.ale.surface_tension import SurfaceTension
from granflow.config import Config
from granflow.fem.flow import Density, FlowSolver
from granflow.fem.forms import FrictionWall
from granflow.fem.linalg import direct_solver
from granflow.fem.measure import AXISYMMETRIC, PLANE, Coordinates
from granflow.fem.mobilisation_field import MobilisationField
from granflow.fem.sampling import triangles
from granflow.geometry.layer_material import LayerMaterial
from granflow.geometry.mesh import BED, END, GATE, SURFACE, WALL
from granflow.geometry.scene import build_scene
from granflow.geometry.stretch import LayerStretch
from granflow.physics import CoulombFriction, Rheology, gravity_vector
from granflow.physics.regions import TwoMaterials, blend
from granflow.scenarios.materials import (
    augmentation,
    build_side_walls,
    friction_law,
    hysteretic,
    layer_material,
)


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


def layer_stretch(config: Config) -> LayerStretch:
    """The erodible layer's cells mesh.layer_aspect times longer along the bed than across
    it (``geometry/stretch.py``; 1, or no layer: isotropic)."""
    return LayerStretch(config.geometry.erodible_thickness, config.mesh.layer_aspect)


def layer_cell_size(config: Config) -> float:
    """The edge length, in the stretched coordinates the mesh is made in, that gives the
    layer mesh.layer_cells cells across: h_e / layer_cells, times mesh.layer_aspect."""
    fine = config.geometry.erodible_thickness / config.mesh.layer_cells
    return min(layer_stretch(config).length(fine), config.mesh.size)


def layer_edge_sizes(config: Config) -> EdgeSize | None:
    """Over an erodible layer of thickness h_e: edges lying within 2 h_e above the bed get
    the layer's cell size (``layer_cell_size``: the bed, the layer's top and its end), so
    that the layer has mesh.layer_cells cells across; Netgen grades the rest up to
    mesh.size."""
    he = config.geometry.erodible_thickness
    if he <= 0:
        return None
    fine, size = layer_cell_size(config), config.mesh.size
    bed = build_scene(config.geometry, config.gate).bed     # heights above the bed profile
    return lambda p, q: fine if bed.height(np.array([p, q])).max() <= 2 * he else size


def layer_end(config: Config, moving_x: float) -> float:
    """Where the meshed erodible layer ends: at geometry.bed_length, or with mesh.layer_ahead
    > 0 that far ahead of the furthest moving material (at the start, the column's foot),
    never beyond geometry.bed_length (``ColumnRemesher`` lengthens it as the flow comes)."""
    geo, ahead = config.geometry, config.mesh.layer_ahead
    return geo.bed_length if ahead <= 0 else min(geo.bed_length, moving_x + ahead)


def coordinates(config: Config) -> Coordinates:
    """Plane strain, or r-z for an axisymmetric column (``fem/measure.py``)."""
    return AXISYMMETRIC if config.geometry.axisymmetric else PLANE


def friction_walls(config: Config) -> list[str]:
    """The boundaries with Coulomb friction and the normal penalty: the bed, the wall at
    x = 0 unless it is the symmetry axis, and the far end of an erodible layer."""
    walls = [BED] if config.geometry.axisymmetric else [BED, WALL]
    walls += [GATE] if config.gate.enabled else []
    return [*walls, END] if config.geometry.erodible_thickness > 0 else walls


def discretise(config: Config, mesh: ngs.Mesh,
               layer: LayerMaterial | None = None) -> ColumnDiscretisation:
    """The flow solver (3.2) with Coulomb walls and the ALE mover (3.6)/(3.7) on ``mesh``;
    in axisymmetry the left boundary is the axis: u_r = 0 there, no friction, no penalty.
    A layer of its own material (``[layer]``) gets the blended law and density, with the
    indicator filled from the tracked region ``layer``."""
    geo, mat, bnd, num = config.geometry, config.material, config.boundary, config.numerics
    load = bnd.normal_load
    walls = [FrictionWall(BED, CoulombFriction(bnd.bed_friction_deg, num.eps_friction), load)]
    if not geo.axisymmetric:
        walls.append(FrictionWall(WALL, CoulombFriction(bnd.wall_friction_deg,
                                                        num.eps_friction), load))
    if geo.erodible_thickness > 0:   # the layer's far end: frictionless, u.N = 0 (domains.py)
        walls.append(FrictionWall(END, CoulombFriction(0.0, num.eps_friction), load))
    scene = build_scene(geo, config.gate)     # the bed profile, the walls, a gate
    gate_speed = ngs.Parameter(0.0) if scene.gate is not None else None
    if scene.gate is not None:     # slides up along itself: friction against its motion
        walls.append(FrictionWall(GATE, CoulombFriction(scene.gate.friction_deg,
                                                        num.eps_friction), load,
                                  velocity=gate_speed * ngs.CF(scene.gate.line.direction)))
    st = config.surface_tension
    mobilisation = MobilisationField(mesh) if hysteretic(config) else None
    rheology, density, fraction = _materials(config, mesh, mobilisation)
    solver = FlowSolver(mesh, rheology=rheology, density=density,
                        body_force=gravity_vector(mat.gravity, geo.slope_deg),
                        walls=walls, penalty=bnd.penalty, linearization=num.linearization,
                        linear_solver=direct_solver(num.linear_solver),
                        initial_guess=num.initial_guess,
                        surface_tension_on=SURFACE if st.enabled else None,
                        side_walls=build_side_walls(config),
                        augmentation=augmentation(config),
                        scheme=config.time.scheme, coordinates=coordinates(config),
                        axis=WALL if geo.axisymmetric else "",
                        anderson_depth=num.anderson_depth)
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
                        measure=polygon_measure(geo.axisymmetric),
                        support=Support(scene.bed, scene.wall), gate=scene.gate,
                        gate_speed=gate_speed)
    out = ColumnDiscretisation(mesh, solver, mover, fraction, mobilisation)
    out.set_fraction(layer)
    return out


def _materials(config: Config, mesh: ngs.Mesh, mobilisation: MobilisationField | None
               ) -> tuple[Rheology, Density, ngs.GridFunction | None]:
    """One material: [material]'s law and density. A layer of its own: both blended with
    the indicator, a piecewise constant share of layer material per triangle, read on the
    walls from the adjacent triangle (a plain L2 function is 0 on a boundary element, which
    would give the Coulomb walls' load under the layer the column's law). A hysteretic
    friction reads the mobilisation field (``fem/mobilisation_field.py``)."""
    eps = config.numerics.eps
    state = (mobilisation.cf, mobilisation.state) if mobilisation is not None else (0.0, None)
    layer = layer_material(config)
    if layer is None:
        return friction_law(config.material, eps, *state), config.material.density, None
    per_triangle = ngs.GridFunction(ngs.L2(mesh, order=0))
    share = ngs.BoundaryFromVolumeCF(per_triangle)
    law = TwoMaterials(friction_law(config.material, eps, *state),
                       friction_law(layer, eps, *state), share, per_triangle)
    return law, blend(config.material.density, layer.density, share), per_triangle
