"""granflow: 2D viscoplastic granular flows with a free surface (regularised Drucker-Prager,
Taylor-Hood finite elements, ALE), built on NGSolve.

Importing the package is cheap: the finite-element engine is imported only by the modules
that need it.
"""

__version__ = "0.1.0"
