"""Constitutive laws, independent of any finite-element engine."""

from granflow.physics.friction import CoulombFriction
from granflow.physics.gravity import gravity_vector
from granflow.physics.ops import NUMPY_OPS, Ops
from granflow.physics.rheology import DruckerPrager

__all__ = ["NUMPY_OPS", "CoulombFriction", "DruckerPrager", "Ops", "gravity_vector"]
