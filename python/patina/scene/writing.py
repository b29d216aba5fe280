"""A parsed scene back to its canonical JSON (every default written out, paths absolute):
what a render's EXR header records, and what round-trips through `parse_scene`."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from patina.scene.types import CarpaintMaterial, ConductorMaterial, Light, Material, MeshLight, Scene, Shape


def _plain(value: Any) -> Any:
    """Dataclasses, tuples and arrays as JSON values ("type" first)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        d = {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
        if "type" in d:
            d = {"type": d.pop("type"), **d}
        return d
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (tuple, list)):
        return [_plain(v) for v in value]
    return value


def _material_json(m: Material) -> dict[str, Any]:
    d = _plain(m)
    if isinstance(m, ConductorMaterial):
        if m.metal is None:
            del d["metal"]
        else:
            del d["eta"], d["k"]
    if isinstance(m, CarpaintMaterial):
        del d["base"]["two_sided"]
    return d


def _shape_json(s: Shape) -> dict[str, Any]:
    d = _plain(s)
    d["transform"] = {"matrix": d["transform"]}
    return d


def _light_json(light: Light) -> dict[str, Any]:
    d = _plain(light)
    if isinstance(light, MeshLight):
        del d["material"]  # a mesh light's own placement, no material
        d["transform"] = {"matrix": d["transform"]}
    return d


def scene_to_json(scene: Scene) -> dict[str, Any]:
    """The scene as canonical JSON values: every default written out, paths absolute.

    `parse_scene(scene_to_json(s), s.path) == s`.
    """
    camera = _plain(scene.camera)
    if scene.camera.type == "pinhole":
        del camera["aperture_radius"], camera["focus_distance"]
    out: dict[str, Any] = {
        "version": scene.version,
        "camera": camera,
        "render": _plain(scene.render),
        "materials": {name: _material_json(m) for name, m in scene.materials.items()},
        "shapes": [_shape_json(s) for s in scene.shapes],
        "lights": [_light_json(light) for light in scene.lights],
    }
    if scene.environment is not None:
        out["environment"] = _plain(scene.environment)
    return out
