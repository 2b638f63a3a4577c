"""A 3D column's set-up, resolved once from its configuration: the section (the built-in
rectangle or trapezoid, X along the bed, Z normal to it), where it lies across the channel
(``ChannelSpan``: the whole channel of width boundary.channel_width between its side
walls, its half beside the centre plane, or without side walls a slab one mesh.size thick
between two frictionless planes), the run's materials, and the flow solver's frozen parts
(``scenarios/flow_config.py``): Coulomb friction with the penalty (2.7)-(2.8) on the bed,
the back wall and the side walls, a frictionless symmetry plane; or, with
boundary.non_penetration = "strong", u.N = 0 held by the space on these planes (each is
normal to an axis: the bed Z = 0, the back wall X = 0, the side and centre planes Y =
const) and the friction alone as their term."""

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
        walls = channel_walls(config, span)
        strong = config.boundary.non_penetration == "strong"
        layout = Layout(SPACE, walls, surface="", held=held_planes(span) if strong else ())
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
    penalised = bnd.non_penetration == "penalty"
    return tuple(FrictionWall(label, CoulombFriction(angles[label], eps), bnd.normal_load,
                              penalised=penalised) for label in labels)


def held_planes(span: ChannelSpan) -> tuple[str, str, str]:
    """The regions where u_x, u_y and u_z vanish: the back wall X = 0, the faces Y = low
    and high, the bed Z = 0 (``ChannelSpan.planes``)."""
    by_axis: dict[int, list[str]] = {0: [], 1: [], 2: []}
    for axis, _, label in span.planes():
        if label not in by_axis[axis]:
            by_axis[axis].append(label)
    x, y, z = ("|".join(by_axis[axis]) for axis in range(3))
    return x, y, z
