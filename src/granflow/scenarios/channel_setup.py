"""A 3D column's set-up, resolved once from its configuration: the section (the built-in
rectangle or trapezoid, X along the bed, Z normal to it), where it lies across the channel
(``ChannelSpan``: the whole channel of width boundary.channel_width between its side
walls, its half beside the centre plane, or without side walls a slab one mesh.size thick
between two frictionless planes), the run's materials, and the flow solver's frozen parts
(``scenarios/flow_config.py``): Coulomb friction with the penalty (2.7)-(2.8) on the bed,
the back wall and the side walls, a frictionless symmetry plane."""

from __future__ import annotations

from dataclasses import dataclass

from granflow.config import Config
from granflow.fem.flow_spec import FlowSpec
from granflow.fem.forms import FrictionWall
from granflow.fem.measure import SPACE
from granflow.geometry.domains import Polygon, column
from granflow.geometry.labels import BED, SIDE, SYMMETRY, WALL
from granflow.geometry.mesh3d import ChannelSpan
from granflow.physics import CoulombFriction
from granflow.scenarios.flow_config import Layout, flow_spec
from granflow.scenarios.materials import RunMaterials, run_materials


@dataclass(frozen=True)
class ChannelSetup:
    """What a 3D column run is made of (module docstring)."""

    config: Config
    section: Polygon
    span: ChannelSpan
    materials: RunMaterials
    flow: FlowSpec

    @classmethod
    def of(cls, config: Config) -> ChannelSetup:
        geo, bnd = config.geometry, config.boundary
        section = column(geo.shape, geo.width, geo.height, geo.front_angle_deg)
        span = (ChannelSpan.slab(config.mesh.size) if bnd.channel_width is None
                else ChannelSpan.channel(bnd.channel_width, geo.half_channel))
        materials = run_materials(config)
        layout = Layout(SPACE, channel_walls(config, span), surface="")
        return cls(config, section, span, materials, flow_spec(config, materials, layout))

    @property
    def size(self) -> float:
        return self.config.mesh.size

    def wall_labels(self) -> list[str]:
        """The boundaries with the normal penalty (all but the free surface)."""
        return [wall.region for wall in self.flow.terms.walls]


def channel_walls(config: Config, span: ChannelSpan) -> tuple[FrictionWall, ...]:
    """The Coulomb walls of a 3D column: the bed (boundary.bed_friction_deg), the back wall
    (boundary.wall_friction_deg), the side walls (boundary.side_wall_friction_deg) and a
    symmetry plane (no friction: u.N = 0 alone)."""
    bnd, eps = config.boundary, config.numerics.eps_friction
    angles = {BED: bnd.bed_friction_deg, WALL: bnd.wall_friction_deg,
              SIDE: bnd.side_wall_friction_deg, SYMMETRY: 0.0}
    labels = [BED, WALL, *dict.fromkeys((span.low_label, span.high_label))]
    return tuple(FrictionWall(label, CoulombFriction(angles[label], eps), bnd.normal_load)
                 for label in labels)
