"""The MPI ranks this process runs among (``mpiexec -n N granflow ...``), read from the
launcher's environment (MPICH's or Open MPI's), so that a serial run needs no MPI installed
and the command line asks without importing the finite-element engine.

In NGSolve's layout rank 0 keeps no element of a distributed mesh: it gathers (the direct
solver's matrix, ``fem/linalg.py``) and the other ranks assemble; rank 0 alone runs the
program and writes the outputs, the others serve its flow solves
(``fem/distributed_flow.py``).
"""

from __future__ import annotations

import os


def world_size() -> int:
    """The number of MPI ranks this process was started with: 1 without ``mpiexec``."""
    size = os.environ.get("PMI_SIZE") or os.environ.get("OMPI_COMM_WORLD_SIZE")
    return int(size) if size else 1


def world_rank() -> int:
    """This process's MPI rank (0 without ``mpiexec``): the one that writes the outputs."""
    rank = os.environ.get("PMI_RANK") or os.environ.get("OMPI_COMM_WORLD_RANK")
    return int(rank) if rank else 0
