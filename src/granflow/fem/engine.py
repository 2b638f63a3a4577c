"""NGSolve process settings, the constitutive-law ops shim for coefficient functions and
the laws as a boundary integral reads them."""

from __future__ import annotations

import ngsolve as ngs

from granflow.physics.ops import Ops
from granflow.physics.rheology import Rheology

# Threads hurt on small 2D problems on these machines (measured: docs/performance.md).
ngs.SetNumThreads(1)

NGSOLVE_OPS = Ops(sqrt=ngs.sqrt, positive_part=lambda a: ngs.IfPos(a, a, 0.0))


def read_on_walls(law: Rheology) -> Rheology:
    """``law`` as a boundary integral reads it: the fields it holds per triangle (a
    hysteretic friction's state, the share of a layer's material) taken from the adjacent
    triangle, where a piecewise constant field would be 0."""
    with_fields = getattr(law, "with_fields", None)
    return law if with_fields is None else with_fields(ngs.BoundaryFromVolumeCF)  # type: ignore
