"""Finite-element discretisation with NGSolve: the only package that imports it."""
