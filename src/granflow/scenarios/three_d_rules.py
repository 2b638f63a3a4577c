"""What a run in three dimensions (``geometry.dimension = 3``) cannot have yet, and the
keys without effect there, for both kinds' rules (``column_rules``, ``plug_flow_rules``).
Engine-free: the configuration is checked before any mesh exists. Each refusal is one
line naming the key; what is refused is what is not verified in 3D (docs/three_d.md)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING

from granflow.scenarios.column_geometry_rules import erodible

if TYPE_CHECKING:
    from granflow.config.schema import ConfigModel as Config

LAWS_3D = ("drucker-prager", "mu-i")     # the laws verified in 3D
THREE_D = "geometry.dimension = 3"


def three_d(c: Config) -> bool:
    """Whether the run is three-dimensional."""
    return c.geometry.dimension == 3


def three_d_problems(c: Config) -> Iterator[str]:
    """What neither kind can have in 3D: a law not verified there, a packing fraction, a
    hysteretic friction, the augmented Lagrangian (its multipliers are 2 x 2 tensors),
    surface tension (built on a section's boundary curve); and what only 3D has, asked
    for in 2D."""
    if not three_d(c):
        yield from _three_d_only(c)
        return
    m = c.material
    if m.rheology not in LAWS_3D:
        yield (f"material.rheology = {m.rheology!r} is not verified in 3D ({THREE_D}); "
               f"use one of {', '.join(map(repr, LAWS_3D))}")
    if m.packing != "none":
        yield (f"material.packing = {m.packing!r} is not verified in 3D ({THREE_D}); "
               "use 'none'")
    if m.friction != "constant":
        yield (f"material.friction = {m.friction!r} is not verified in 3D ({THREE_D}); "
               "use 'constant'")
    if c.numerics.method == "augmented-lagrangian":
        yield (f"numerics.method = 'augmented-lagrangian' works on 2 x 2 tensors; use "
               f"'regularized' with {THREE_D}")
    if c.surface_tension.enabled:
        yield ("surface_tension.enabled = true: the numerical surface tension (3.8)-(3.11) "
               f"acts on a section's boundary curve, not in 3D ({THREE_D}); set it false")


def _three_d_only(c: Config) -> Iterator[str]:
    """What a run in two dimensions cannot ask for: the walls held strongly (its walls
    keep the penalty (2.7), as verified), PETSc's fieldsplit solve (its sections are
    solved faster by the direct solve, and GAMG is unmeasured against the penalty walls'
    contrast)."""
    if c.boundary.non_penetration == "strong":
        yield (f"boundary.non_penetration = 'strong' holds u.N = 0 on the walls of a 3D "
               f"column ({THREE_D}); use 'penalty' in 2D")
    if c.numerics.linear_solver == "fieldsplit":
        yield (f"numerics.linear_solver = 'fieldsplit' is the iterative solve of 3D runs "
               f"({THREE_D}); use 'auto' in 2D")


def column_3d_problems(c: Config) -> Iterator[str]:
    """A 3D column is the built-in rectangle or trapezoid on the level rigid bed (a
    slope through gravity) against the back wall, in a channel: no cylinder, no
    erodible layer, no gate, no user's bed or mass."""
    if not three_d(c):
        return
    g = c.geometry
    if g.axisymmetric:
        yield (f"geometry.axisymmetric = true describes an r-z section; use it with "
               f"geometry.dimension = 2, not {THREE_D}")
    if erodible(c):
        yield (f"geometry.erodible_thickness = {g.erodible_thickness!r}: an erodible layer is "
               f"not available in 3D ({THREE_D}); use 0")
    if c.gate.enabled:
        yield f"gate.enabled = true: a gate is not available in 3D ({THREE_D}); set it false"
    for key in ("bed_profile", "bed_profile_file", "mass", "mass_file"):
        if getattr(g, key) is not None:
            yield (f"geometry.{key} is set: a 3D column is the built-in geometry.shape on the "
                   f"level bed ({THREE_D}); unset it")
    if not g.left_wall:
        yield (f"geometry.left_wall = false: a 3D column stands against its back wall "
               f"({THREE_D}); set it true")
    if c.boundary.bed != "coulomb":
        yield (f"boundary.bed = {c.boundary.bed!r} is not verified in 3D ({THREE_D}); "
               "use 'coulomb'")
    b = c.boundary
    if b.non_penetration == "strong" and b.normal_load == "reaction":
        yield ("boundary.normal_load = 'reaction' is the penalty's normal traction, and "
               "boundary.non_penetration = 'strong' has no penalty; use 'pressure'")


def layer_3d_problems(c: Config) -> Iterator[str]:
    """The 3D periodic layer runs on its fixed box."""
    if three_d(c) and c.numerics.mesh_velocity != "fixed":
        yield (f"numerics.mesh_velocity = {c.numerics.mesh_velocity!r}: the 3D periodic "
               f"layer ({THREE_D}) runs on a fixed mesh; use 'fixed'")


def three_d_inert_keys(c: Config, column: bool) -> dict[str, str]:
    """The keys without effect in this dimension, with the reason, for a column or (not
    ``column``) a periodic layer."""
    out: dict[str, str] = {}

    def add(keys: str, reason: str) -> None:
        out.update(dict.fromkeys(keys.split(), reason))

    if not three_d(c):
        add("geometry.half_channel", "it halves a 3D channel, and geometry.dimension = 2")
        return out
    if not column:
        add("geometry.half_channel mesh.cells_x",
            f"the 3D periodic layer ({THREE_D}) is a box of cells of mesh.size")
        add("boundary.non_penetration", f"the 3D periodic layer ({THREE_D}) has no walls")
        return out
    add("mesh.adaptive mesh.rest_coarsening mesh.flow_margin",
        f"a 3D column ({THREE_D}) is meshed with the uniform mesh.size")
    if c.boundary.channel_width is None:
        add("geometry.half_channel", "boundary.channel_width = none: the 3D column lies "
            "between two frictionless planes one mesh.size apart (no channel to halve)")
    return out
