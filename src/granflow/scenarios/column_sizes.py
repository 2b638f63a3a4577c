"""The size field of a column's mesh (``ale/size_field.py``) from its configuration and
its flow: what the first mesh and every remesh are made with when ``mesh.adaptive`` is on.

Moving material is where the speed of u^n at a vertex exceeds the flowing threshold (the
cells that ``flowing_fraction`` counts), or where the shear rate sqrt(2) |Du| of a cell exceeds
``RATE`` (a layer sheared under a slow flow). At the start the column is at rest but about
to collapse: its bulk is fine everywhere and the layer under it and ahead of its foot;
every remesh then refits the field to the flow (``flow_size_field``)."""

from __future__ import annotations

import ngsolve as ngs
import numpy as np

from granflow.ale.mesh_motion import vertex_values
from granflow.ale.size_field import LEAD, SizeField, flow_size_field
from granflow.diagnostics.state import FLOWING_SPEED
from granflow.fem.sampling import cell_means, triangles
from granflow.scenarios.column_discretisation import ColumnDiscretisation
from granflow.scenarios.column_setup import ColumnSetup

RATE = 1.0   # 1/s: a cell sheared faster moves (at rest the regularised law creeps at ~eps)


def base_size_field(setup: ColumnSetup) -> SizeField | None:
    """The sizes of ``[mesh]`` (no windows yet), or None when the mesh is uniform:
    ``mesh.adaptive`` off, or nothing to adapt (a rigid bed whose bulk keeps mesh.size)."""
    m, he = setup.config.mesh, setup.thickness
    if not m.adaptive or (not setup.erodible and m.rest_coarsening == 1):
        return None
    coarse = m.size * m.rest_coarsening
    fine_layer = setup.layer_cell_size() if setup.erodible else 0.0
    coarse_layer = min(m.layer_rest_coarsening * fine_layer, coarse)
    return SizeField(m.size, coarse, fine_layer, max(fine_layer, coarse_layer), he,
                     m.flow_margin * m.size)


def initial_size_field(setup: ColumnSetup, end_x: float) -> SizeField | None:
    """The first mesh's field: the bulk fine everywhere, the layer fine from the wall to
    LEAD margins beyond the column's foot (``geometry.width``), within its meshed end."""
    base = base_size_field(setup)
    if base is None:
        return None
    windows = np.array([[0.0, min(setup.config.geometry.width + LEAD * base.margin, end_x)]])
    return SizeField(base.fine, base.coarse, base.layer_fine, base.layer_coarse,
                     base.layer_top, base.margin, windows, None)


def moving_vertices(current: ColumnDiscretisation) -> np.ndarray:
    """Flags per vertex of the current mesh: moving material (module docstring)."""
    mesh = current.mesh
    u = current.solver.previous.components[0]
    moving = np.linalg.norm(vertex_values(u), axis=1) > FLOWING_SPEED
    rate, _ = cell_means(mesh, ngs.sqrt(2.0 * current.solver.coordinates.strain_rate_sq(u)))
    moving[np.unique(triangles(mesh)[rate > RATE])] = True
    return moving


def refitted(setup: ColumnSetup, current: ColumnDiscretisation, field: SizeField,
             end_x: float) -> SizeField:
    """``field``'s sizes refitted to the current flow (``flow_size_field``), the layer
    meshed to ``end_x``."""
    xy = current.mesh.ngmesh.Coordinates()
    return flow_size_field(field, xy.copy(), moving_vertices(current),
                           setup.bed.height, end_x)


def refit_due(setup: ColumnSetup, current: ColumnDiscretisation, field: SizeField) -> bool:
    """Whether the flow has come within half the margin of coarse cells (``uncovered``) or
    left much of the fine mesh at rest (``overgrown``)."""
    xy = current.mesh.ngmesh.Coordinates()
    moving, heights = xy[moving_vertices(current)], setup.bed.height
    end = current.mover.end_x
    return field.uncovered(moving, heights, end) or field.overgrown(moving, heights, end)


def remesh_sizes(setup: ColumnSetup, field: SizeField) -> dict[str, object]:
    """What ``ale.remesh.remesh`` takes of the field: the largest edge, the boundary edges'
    sizes and the points where the mesh is finer."""
    bed = setup.bed
    return {"maxh": field.maxh, "edge_size": field.edge_size(bed.height),
            "restrict": field.restrictions(bed.z)}
