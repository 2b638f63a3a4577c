"""NGSolve process settings, the constitutive-law ops shim for coefficient functions and
the laws as a boundary integral reads them."""

from __future__ import annotations

import ngsolve as ngs
import pyngcore

from granflow.physics.ops import Ops
from granflow.physics.rheology import Rheology

# Threads hurt on small 2D problems on these machines (measured: docs/performance.md).
ngs.SetNumThreads(1)
# NGSolve's own log shows errors only: its profiler's table of timers fills after some
# thousands of spaces (a long run's remeshes each make a dozen) and it then warned
# "no more timer available (FESpace), reusing last one" on the run's terminal (the timers
# only time NGSolve's own profile, which granflow does not read).
pyngcore.SetLoggingLevel(pyngcore.LOG_LEVEL.Error)

NGSOLVE_OPS = Ops(sqrt=ngs.sqrt, positive_part=lambda a: ngs.IfPos(a, a, 0.0),
                  maximum=lambda a, b: ngs.IfPos(a - b, a, b))


def read_on_walls(law: Rheology) -> Rheology:
    """``law`` as a boundary integral reads it: the fields it holds per triangle (a
    hysteretic friction's state, the share of a layer's material) taken from the adjacent
    triangle, where a piecewise constant field would be 0."""
    with_fields = getattr(law, "with_fields", None)
    return law if with_fields is None else with_fields(ngs.BoundaryFromVolumeCF)  # type: ignore
