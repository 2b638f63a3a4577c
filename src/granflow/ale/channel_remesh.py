"""A new mesh of a 3D column's moved body: its free surface cut at stations across the
channel (``ale/channel_surface.py``), each trace resampled into a closed section with the
bed and the back wall, and the body lofted through them and meshed by Netgen
(``geometry/mesh3d.py: lofted_mesh``). Unlike a volume mesh of the old surface triangles,
the new surface is triangulated afresh: stretched or deposited surface triangles at a
spreading front do not survive a remesh. The loft is the old surface to within its
sampling (about mesh.size): the volume it gains or loses is restored by the mover's
correction of the free surface (``ale/channel_mover.py``)."""

from __future__ import annotations

import math

import ngsolve as ngs
import numpy as np

from granflow.ale.channel_surface import plane_section, section_polygon
from granflow.geometry.mesh3d import ChannelSpan, lofted_mesh
from granflow.simulation.outcomes import MeshingFailed

BED_FLOOR = 0.02    # x mesh.size: the surface this close to the bed at the front is bed


def lofted_remesh(mesh: ngs.Mesh, span: ChannelSpan, size: float) -> ngs.Mesh:
    """A new mesh of ``mesh``'s body with edges of about ``size`` (module docstring): one
    station per ``size`` across the span, one section point per ``size`` along the
    longest trace."""
    stations = max(2, math.ceil(span.width / size - 1e-9) + 1)
    traces = [plane_section(mesh, float(y)) for y in np.linspace(span.low, span.high,
                                                                 stations)]
    if any(len(trace) < 2 for trace in traces):
        raise MeshingFailed("a station across the channel misses the free surface")
    longest = max(float(np.sum(np.linalg.norm(np.diff(t, axis=0), axis=1))) for t in traces)
    count = max(3, math.ceil(longest / size) + 1)
    sections = [section_polygon(trace, count, BED_FLOOR * size) for trace in traces]
    return lofted_mesh(sections, span, size)
