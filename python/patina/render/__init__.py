"""Rendering: a scene made into the C++ renderer's input (prepare, with its materials),
a render run with progress and Ctrl-C (run), its outputs (outputs: EXR with AOVs and
metadata, PNG, exposure), illuminance on sensor grids (illuminance), environment-map
conventions (envmap) and image I/O through OpenImageIO (images)."""

from patina.render.outputs import write_outputs
from patina.render.prepare import PreparedScene
from patina.render.run import RenderResult, render

__all__ = ["PreparedScene", "RenderResult", "render", "write_outputs"]
