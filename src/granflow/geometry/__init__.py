"""Domains, boundary labels and meshes."""
