"""The preview scene of `patina preview`: a material on an object over a grey floor under an
environment map, framed for a 4:3 image, as scene-file JSON (parsed like any scene file)."""

from __future__ import annotations

import os
from typing import Any

from patina.table.formats.tensor_file import MAGIC as TENSOR_FILE_MAGIC


def material_type(material: str) -> str:
    """The scene material a file previews as: a fit.json a fit; an RGL .bsdf (by its tensor_file
    magic: Zemax text shares the extension) the native RGL material, evaluated by the file's own
    rule and sampled by its warps rather than resampled onto a table; any other file a table."""
    if material.endswith(".json"):
        return "fit"
    if material.lower().endswith(".bsdf"):
        try:
            with open(material, "rb") as f:
                if f.read(len(TENSOR_FILE_MAGIC)) == TENSOR_FILE_MAGIC:
                    return "rgl"
        except OSError:
            pass  # the scene reader reports the file
    return "table"


def preview_scene_dict(material: str, env: str, shape: str, coat: bool) -> dict[str, Any]:
    """The preview layout: the object on a grey floor under an environment, framed for a 4:3 image."""
    base: dict[str, Any] = {"type": material_type(material), "file": os.path.abspath(material)}
    mat = {"type": "carpaint", "base": base, "coat": {"eta": 1.5, "roughness": 0.0}} if coat else base
    if shape == "ball":
        obj: dict[str, Any] = {"type": "ball"}
        camera = {"position": [0, 1.7, 5.6], "look_at": [0, 0.95, 0], "fov": 30}
    elif shape == "sphere":
        # the exact sphere: a material preview without facets in its highlights
        obj = {"type": "sphere", "radius": 1, "analytic": True, "transform": {"translate": [0, 1, 0]}}
        camera = {"position": [0, 1.5, 5.0], "look_at": [0, 1, 0], "fov": 30}
    elif shape == "panel":
        obj = {"type": "panel", "transform": {"translate": [0, 1, 0]}}
        camera = {"position": [1.2, 1.6, 4.5], "look_at": [0, 1, 0], "fov": 30}
    else:
        obj = {"type": "mesh", "file": os.path.abspath(shape)}
        camera = {"position": [0, 1.7, 5.6], "look_at": [0, 0.95, 0], "fov": 30}
    camera.update(width=512, height=384)
    return {
        "version": 1,
        "camera": camera,
        "render": {"spp": 32, "integrator": "path", "max_depth": 4},
        "materials": {"material": mat, "floor": {"type": "lambert", "albedo": 0.5}},
        "shapes": [dict(obj, material="material"), {"type": "plane", "material": "floor", "size": [20, 20]}],
        "environment": {"type": "map", "file": os.path.abspath(env)},
    }
