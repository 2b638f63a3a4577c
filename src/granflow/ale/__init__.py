"""Arbitrary Lagrangian–Eulerian mesh motion and free-surface treatment (paper 3.2-3.4)."""
