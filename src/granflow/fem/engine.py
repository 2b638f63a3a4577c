"""NGSolve process settings and the constitutive-law ops shim for coefficient functions."""

from __future__ import annotations

import ngsolve as ngs

from granflow.physics.ops import Ops

# Threads hurt on small 2D problems on these machines (measured: docs/performance.md).
ngs.SetNumThreads(1)

NGSOLVE_OPS = Ops(sqrt=ngs.sqrt, positive_part=lambda a: ngs.IfPos(a, a, 0.0))
