"""Geometry: triangle meshes (mesh), the kd-tree ray tracer's face (accel), the built-in
preview shapes (shapes), and deterministic benchmark and test geometry (benchmark_geometry)."""

from patina.geometry.accel import Accel, Hits
from patina.geometry.mesh import MESH_FORMATS, Mesh, load_mesh

__all__ = ["MESH_FORMATS", "Accel", "Hits", "Mesh", "load_mesh"]
