"""Boundary labels of a column's domain (no finite-element import: the configuration's
checks and the domain builders read them too)."""

from __future__ import annotations

BED, WALL, SURFACE, END, GATE = "bed", "wall", "surface", "end", "gate"
LABELS = (BED, WALL, SURFACE, END, GATE)   # the mesh's boundary regions, in this order
# a three-dimensional column's (``geometry/mesh3d.py``): a channel's side walls, and its
# centre plane when the mesh holds half the channel
SIDE, SYMMETRY = "side", "symmetry"
INTERIOR = "interior"   # a line inside the domain the mesh follows (not a boundary)
