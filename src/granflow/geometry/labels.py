"""Boundary labels of a column's domain (no finite-element import: the configuration's
checks and the domain builders read them too)."""

from __future__ import annotations

BED, WALL, SURFACE, END, GATE = "bed", "wall", "surface", "end", "gate"
LABELS = (BED, WALL, SURFACE, END, GATE)   # the mesh's boundary regions, in this order
INTERIOR = "interior"   # a line inside the domain the mesh follows (not a boundary)
