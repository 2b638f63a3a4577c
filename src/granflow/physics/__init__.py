"""Constitutive laws, independent of any finite-element engine."""

from granflow.physics.friction import CoulombFriction, SideWallFriction
from granflow.physics.gravity import gravity_vector
from granflow.physics.mu_i import MuI
from granflow.physics.ops import NUMPY_OPS, Ops
from granflow.physics.rheology import DruckerPrager, Rheology

__all__ = ["NUMPY_OPS", "CoulombFriction", "DruckerPrager", "MuI", "Ops", "Rheology",
           "SideWallFriction", "gravity_vector"]
