"""Quantities read from the simulation state: errors, conservation, front, interface."""
