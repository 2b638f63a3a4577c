"""granflow: 2D viscoplastic granular flows with a free surface (regularised Drucker-Prager,
Taylor-Hood finite elements, ALE), built on NGSolve.

Importing the package registers the built-in problem kinds with the configuration
(``scenarios/__init__.py``); the finite-element engine is imported only by the modules that
need it.
"""

import os

# One BLAS thread: on these 2D problems extra threads only contend (measured, see
# docs/performance.md); set before numpy or NGSolve load OpenBLAS. An explicit user setting wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")    # PARDISO (MKL): one thread, like NGSolve
# MKL picks its kernels by the CPU, and they round differently: the same run differs in its
# last digits from one machine to another. MKL_CBWR=COMPATIBLE (its SSE2 kernels on every
# x86-64 CPU) makes a run the same everywhere, at a price measured in docs/performance.md
# (Reproducibility) that keeps it a switch, not the default.

__version__ = "0.2.0"

__all__ = ["Config", "Run", "Summary", "load", "resume", "run", "__version__"]
_API = {"run": "granflow.app.api", "load": "granflow.app.api", "resume": "granflow.app.api",
        "Run": "granflow.app.api",
        "Summary": "granflow.app.api", "Config": "granflow.config"}


def __getattr__(name: str) -> object:
    """``granflow.run``, ``granflow.load``, ``granflow.Config``...: imported on first use,
    so that ``import granflow`` (and the command line) stays fast."""
    if name in _API:
        import importlib

        return getattr(importlib.import_module(_API[name]), name)
    raise AttributeError(f"module 'granflow' has no attribute {name!r}")


from granflow import earlier_names as _earlier  # noqa: E402  (granflow.runner, ...)

_earlier.install()

from granflow import scenarios as _kinds  # noqa: E402,F401  (the built-in kinds register)
