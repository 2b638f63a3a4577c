"""NGSolve on MPI ranks: the mesh made on rank 0 and distributed by NGSolve, so that a
script runs unchanged on one process and under ``mpiexec -n N``.

In NGSolve's layout rank 0 keeps no element of a distributed mesh: it gathers (the direct
solver's matrix, ``fem/linalg.py``) and the other ranks assemble. Integrals
(``ngs.Integrate``) and global dof counts (``ndofglobal``) are summed over the ranks;
anything a rank computes from its own vertices alone is not.
"""

from __future__ import annotations

import os
from collections.abc import Callable

import ngsolve as ngs


def world_size() -> int:
    """The number of MPI ranks this process was started with: 1 without ``mpiexec``
    (read from the launcher's environment, MPICH's or Open MPI's, so that a serial run
    needs no MPI installed)."""
    size = os.environ.get("PMI_SIZE") or os.environ.get("OMPI_COMM_WORLD_SIZE")
    return int(size) if size else 1


def world_rank() -> int:
    """This process's MPI rank (0 without ``mpiexec``): the one that writes the outputs."""
    rank = os.environ.get("PMI_RANK") or os.environ.get("OMPI_COMM_WORLD_RANK")
    return int(rank) if rank else 0


def distribute(make: Callable[[], ngs.Mesh]) -> ngs.Mesh:
    """``make()`` on one process; on several ranks, rank 0 makes the mesh and NGSolve
    distributes it, the other ranks receive their parts."""
    if world_size() == 1:
        return make()
    import netgen.meshing
    from mpi4py import MPI  # only under mpiexec: mpi4py is an optional install

    comm = MPI.COMM_WORLD
    if comm.rank == 0:
        ngmesh = make().ngmesh
        ngmesh.Distribute(comm)
    else:
        ngmesh = netgen.meshing.Mesh.Receive(comm)
    return ngs.Mesh(ngmesh)
