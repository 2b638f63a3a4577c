"""Walls held strongly (``fem/held_walls.py``): the space holds each wall's normal velocity
component, and a surface triangle relabelled as a wall (deposition) holds its own from
the next step on."""

import ngsolve as ngs
import numpy as np

from granflow.config import load_config
from granflow.fem.flow_factory import build_flow
from granflow.fem.held_walls import HeldWalls, held_dofs
from granflow.geometry.labels import BED, SURFACE
from granflow.geometry.mesh3d import extruded_mesh
from granflow.scenarios.channel_setup import ChannelSetup, held_planes

SETS = ["geometry.dimension=3", "mesh.size=0.07", "boundary.channel_width=0.1",
        "boundary.non_penetration=strong"]


def _component_dofs(space: ngs.FESpace, face: int, component: int) -> set[int]:
    """The degrees of freedom of one velocity component on one boundary face."""
    n = space.components[0].ndof // 3
    dofs = [d for d in space.GetDofNrs(ngs.ElementId(ngs.BND, face)) if 0 <= d < 3 * n]
    return {d for d in dofs if d // n == component}


def test_the_planes_normal_to_each_axis() -> None:
    setup = ChannelSetup.of(load_config("rectangle-rigid", SETS))
    assert held_planes(setup.span) == ("wall", "symmetry|side", "bed")
    assert all(not w.penalised for w in setup.flow.terms.walls)


def test_a_deposited_triangle_holds_its_normal_velocity() -> None:
    setup = ChannelSetup.of(load_config("rectangle-rigid", SETS))
    mesh = extruded_mesh(setup.section, setup.span, setup.size)
    solver = build_flow(mesh, setup.flow)
    space = solver.space
    names = list(mesh.GetBoundaries())
    faces = mesh.ngmesh.Elements2D().NumPy()
    labels = faces["index"]
    xyz = mesh.ngmesh.Coordinates()
    front = xyz[faces["nodes"][:, :3].astype(int) - 1, 0].min(axis=1)    # away from X = 0
    bed = max((k for k, index in enumerate(labels) if names[index - 1] == BED),
              key=lambda k: front[k])
    top = next(k for k, index in enumerate(labels) if names[index - 1] == SURFACE)
    held = held_dofs(space)
    assert all(held[d] for d in _component_dofs(space, bed, 2))        # u_z on the bed
    assert not any(held[d] for d in _component_dofs(space, bed, 0))    # u_x slides
    top_z = _component_dofs(space, top, 2) - _component_dofs(space, bed, 2)
    assert top_z and not any(held[d] for d in top_z)
    solver.solution.vec.FV().NumPy()[:] = 1.0
    labels[top] = names.index(BED) + 1                                 # deposited
    held_walls = solver.coupling(HeldWalls)
    assert held_walls is not None
    held_walls.start_step(1e-3)
    held = held_dofs(space)
    assert all(held[d] for d in top_z)
    values = solver.solution.vec.FV().NumPy()
    assert np.all(values[sorted(top_z)] == 0.0)
    assert np.all(values[~held] == 1.0)                                # nothing else
