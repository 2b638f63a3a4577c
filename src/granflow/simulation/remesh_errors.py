"""Errors from a remesh, sorted: the mesher's failures, which the loop answers by going on
(a smaller step, or the mesh it has), and defects, which end the run at once.

A mesher's failure is a type the scenario names (``Simulation.mesher_failures``: our
``MeshingFailed``, Netgen's ``NgException``, the RuntimeErrors of the remesh's geometry
checks). Anything else (TypeError, AttributeError, NameError, ...) is a defect in granflow:
retrying it would only hide it while the run crawls on a mesh that degrades.
"""

from __future__ import annotations

import traceback

# RuntimeErrors that are never the mesher's (its failures may be RuntimeErrors)
DEFECTS: tuple[type[Exception], ...] = (NotImplementedError, RecursionError)


class RemeshDefect(Exception):
    """A remesh raised an error that is not the mesher's: the run stops with ``message``."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


def mesher_failed(exc: Exception, failures: tuple[type[Exception], ...]) -> bool:
    """Whether ``exc`` is the mesher's failure (one of ``failures``, not a ``DEFECTS``)."""
    return isinstance(exc, failures) and not isinstance(exc, DEFECTS)


def defect_message(exc: Exception, step: int, t: float) -> str:
    """When (after accepted step ``step``, at t) and where a remesh raised a defect, and
    what to do about it."""
    frames = traceback.extract_tb(exc.__traceback__)
    where = (f" in {frames[-1].name} ({frames[-1].filename.rsplit('/', 1)[-1]}:"
             f"{frames[-1].lineno})" if frames else "")
    return (f"after step {step} at t = {t:.6g} s: remeshing raised {type(exc).__name__}{where}: "
            f"{exc}. This is a defect in granflow, not a mesh the mesher refused (those "
            "are retried with smaller steps): report it with the run's config.toml; "
            "mesh.remesh_quality = 0 avoids the remeshes the mesh's quality asks for")
