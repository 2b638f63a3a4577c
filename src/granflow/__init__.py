"""granflow: 2D viscoplastic granular flows with a free surface (regularised Drucker-Prager,
Taylor-Hood finite elements, ALE), built on NGSolve.

Importing the package is cheap: the finite-element engine is imported only by the modules
that need it.
"""

import os

# One BLAS thread: on these 2D problems extra threads only contend (DESIGN.md, measured
# facts); set before numpy or NGSolve load OpenBLAS. An explicit user setting wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")    # PARDISO (MKL): one thread, like NGSolve

__version__ = "0.1.0"
