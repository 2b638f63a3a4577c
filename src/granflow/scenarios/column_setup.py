"""A column run's set-up, resolved once from its configuration: the scene (the bed, the
walls, the mass and the meshed erodible layer, ``geometry/scene.py``; a bed profile's file
is read here and nowhere else), plane or r-z coordinates (``fem/measure.py``), the run's
materials (an erodible layer's own, or none: ``scenarios/materials.py``) and how the layer
is meshed, and the flow solver's frozen parts (``scenarios/flow_config.py``: its walls,
the axis, the surface). Every part of a collapse (the discretisation, the remesher, the size
field, the measures, the layer tracking, the figures) reads these from one frozen ``ColumnSetup``,
which is the one home of three questions: is there an erodible layer (``erodible``), is the
bed the paper's level bed z = 0 from x = 0 (``paper_bed``), is the run axisymmetric
(``coordinates``)."""

from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from granflow.ale.remesh import EdgeSize
from granflow.config import Config
from granflow.config.kinds import erodible_layer
from granflow.fem.flow_spec import FlowSpec
from granflow.fem.forms import FrictionWall
from granflow.fem.measure import Coordinates, coordinates_of
from granflow.geometry.mesh import END, GATE, SURFACE, WALL
from granflow.geometry.profile import BedProfile
from granflow.geometry.scene import Scene, build_scene
from granflow.geometry.stretch import LayerStretch
from granflow.physics import CoulombFriction
from granflow.scenarios.bed import bed_wall, rough_bed
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.materials import RunMaterials, run_materials


@dataclass(frozen=True)
class ColumnSetup:
    """What a column run is made of, built once by ``of`` (module docstring). ``config``
    stays for the plain numbers each part reads of it (sizes, tolerances, times)."""

    config: Config
    scene: Scene
    coordinates: Coordinates
    materials: RunMaterials
    erodible: bool                    # an erodible layer (geometry.erodible_thickness > 0)
    flow: FlowSpec
    gate_speed: ngs.Parameter | None  # a gate's, set by the mover, read by its wall

    @classmethod
    def of(cls, config: Config) -> ColumnSetup:
        """The set-up of ``config``: the scene's meshed layer ends at ``layer_end``; a layer
        of its own material starts with its top under the column as an interior line of
        the mesh."""
        materials = run_materials(config)
        geo = config.geometry
        end = layer_end(config, geo.width)
        scene = build_scene(geo, config.gate, end, interface=materials.layer is not None)
        coordinates, erodible = coordinates_of(geo), erodible_layer(config)
        gate_speed = ngs.Parameter(0.0) if scene.gate is not None else None
        layout = Layout(coordinates, column_walls(config, scene, coordinates, erodible,
                                                  gate_speed),
                        axis=WALL if coordinates.axisymmetric else "",
                        rough=rough_bed(config),
                        surface=SURFACE)
        return cls(config, scene, coordinates, materials, erodible,
                   flow_spec(config, materials, layout), gate_speed)

    @property
    def bed(self) -> BedProfile:
        """The bed profile z_b(x) (the level line z = 0 without a profile)."""
        return self.scene.bed

    @property
    def paper_bed(self) -> bool:
        """Whether the bed is the paper's: the level line z = 0 from the wall at x = 0 (no
        ``geometry.bed_profile`` or ``bed_profile_file``)."""
        return self.scene.default_bed

    @property
    def axisymmetric(self) -> bool:
        """Whether x is the radius r of a cylinder (``coordinates``)."""
        return self.coordinates.axisymmetric

    @property
    def thickness(self) -> float:
        """The erodible layer's thickness h_e (0 on a rigid bed)."""
        return self.config.geometry.erodible_thickness if self.erodible else 0.0

    # --- how the layer is meshed -----------------------------------------------------
    @property
    def stretch(self) -> LayerStretch:
        """The erodible layer's cells mesh.layer_aspect times longer along the bed than
        across it (``geometry/stretch.py``; 1, or no layer: isotropic)."""
        return LayerStretch(self.config.geometry.erodible_thickness,
                            self.config.mesh.layer_aspect)

    def layer_cell_size(self) -> float:
        """The edge length, in the stretched coordinates the mesh is made in, that gives
        the layer mesh.layer_cells cells across: h_e / layer_cells, times
        mesh.layer_aspect (mesh.size on a rigid bed)."""
        if not self.erodible:
            return self.config.mesh.size
        fine = self.thickness / self.config.mesh.layer_cells
        return min(self.stretch.length(fine), self.config.mesh.size)

    def layer_edge_sizes(self) -> EdgeSize | None:
        """Over an erodible layer of thickness h_e: edges lying within 2 h_e above the bed
        get the layer's cell size (``layer_cell_size``: the bed, the layer's top and its
        end), so that the layer has mesh.layer_cells cells across; Netgen grades the rest
        up to mesh.size."""
        if not self.erodible:
            return None
        he, fine, size = self.thickness, self.layer_cell_size(), self.config.mesh.size
        bed = self.bed
        return lambda p, q: fine if bed.height(np.array([p, q])).max() <= 2 * he else size

    def layer_end(self, moving_x: float) -> float:
        """Where the meshed erodible layer ends (``layer_end``)."""
        return layer_end(self.config, moving_x)


def layer_end(config: Config, moving_x: float) -> float:
    """Where the meshed erodible layer ends: at geometry.bed_length, or with mesh.layer_ahead
    > 0 that far ahead of the furthest moving material (at the start, the column's foot),
    never beyond geometry.bed_length (``ColumnRemesher`` lengthens it as the flow comes)."""
    geo, ahead = config.geometry, config.mesh.layer_ahead
    return geo.bed_length if ahead <= 0 else min(geo.bed_length, moving_x + ahead)


def column_walls(config: Config, scene: Scene, coordinates: Coordinates, erodible: bool,
                 gate_speed: ngs.Parameter | None) -> tuple[FrictionWall, ...]:
    """The walls: the bed (``boundary.bed``, ``scenarios/bed.py``), the Coulomb wall at
    x = 0 unless it is the symmetry axis (in axisymmetry u_r = 0 there, no friction, no
    penalty), the far end of an erodible layer (frictionless, u.N = 0), and a gate sliding
    up along itself (friction against its motion)."""
    bnd, eps = config.boundary, config.numerics.eps_friction
    load = bnd.normal_load
    walls = [bed_wall(config)]
    if not coordinates.axisymmetric:
        walls.append(FrictionWall(WALL, CoulombFriction(bnd.wall_friction_deg, eps), load))
    if erodible:
        walls.append(FrictionWall(END, CoulombFriction(0.0, eps), load))
    if scene.gate is not None and gate_speed is not None:
        walls.append(FrictionWall(GATE, CoulombFriction(scene.gate.friction_deg, eps), load,
                                  velocity=gate_speed * ngs.CF(scene.gate.line.direction)))
    return tuple(walls)
