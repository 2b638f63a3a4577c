"""Constitutive laws, independent of any finite-element engine. Importing the package
registers every law with ``laws.py`` (each at the end of its module)."""

from granflow.physics.friction import CoulombFriction, SideWallFriction
from granflow.physics.gravity import gravity_vector, gravity_vector_3d
from granflow.physics.hysteresis import Hysteretic
from granflow.physics.mu_i import MuI
from granflow.physics.nonlocal_fluidity import NonlocalFluidity
from granflow.physics.ops import NUMPY_OPS, Ops
from granflow.physics.packing import CriticalState, Dilatant
from granflow.physics.rheology import DruckerPrager, Rheology

__all__ = ["NUMPY_OPS", "CoulombFriction", "CriticalState", "Dilatant", "DruckerPrager",
           "Hysteretic", "MuI", "NonlocalFluidity", "Ops", "Rheology", "SideWallFriction",
           "gravity_vector", "gravity_vector_3d"]
