"""The bench's scenes as Mitsuba 3 renders them: the same triangles, and Mitsuba's nearest
BSDFs where Patina's material has no exact equivalent.

`materials/scenes/preview-mitsuba.json` is the preview ball with materials of the kinds
Mitsuba also has: the car paint's fitted GGX + Lambert (`materials/carpaint-base-fit.json`)
under a smooth coat on the ball, a GGX gold sphere and a rough plastic sphere (Lambert
under a rough coat) beside it. The gold is converted exactly (patina.scene.mitsuba). The
coated materials are not: Mitsuba 3 has no coat over an arbitrary base, and its
`roughplastic` scales the diffuse term for internal reflections where Patina's coat does
not. So the stand-ins are the nearest Mitsuba materials of the same structure (a GGX coat
over a diffuse base: `roughplastic`; a GGX lobe and a diffuse term under a clear coat:
`principled` with `clearcoat` 1), and a comparison of speed on this scene measures each
renderer's error against its own converged image (bench/render.py).
"""

from __future__ import annotations

import dataclasses
import json
import math
from typing import Any

from patina.bundled import materials_path
from patina.render.prepare import shape_mesh
from patina.scene.mitsuba import to_mitsuba
from patina.scene.reading import load_scene, with_overrides
from patina.scene.types import CarpaintMaterial, FitMaterial, LambertMaterial, Scene, Shape, SphereShape


def preview_mitsuba_scene(width: int, height: int) -> Scene:
    """materials/scenes/preview-mitsuba.json at width x height, seed 0."""
    return with_overrides(
        load_scene(materials_path("scenes", "preview-mitsuba.json")), width=width, height=height, seed=0
    )


def _rgb(value: Any) -> dict[str, Any]:
    return {"type": "rgb", "value": [float(x) for x in value]}


def stand_in_bsdf(material: CarpaintMaterial, where: str) -> dict[str, Any]:
    """Mitsuba's nearest BSDF to a car paint: `roughplastic` (`plastic` when smooth) for a Lambert
    base, `principled` with a clear coat for a fitted GGX + Lambert base (base colour the fit's
    diffuse albedo, roughness the square root of its alpha, specular from its mean F0)."""
    coat = material.coat
    base = material.base
    if isinstance(base, LambertMaterial):
        out: dict[str, Any] = {
            "type": "roughplastic" if coat.roughness > 0 else "plastic",
            "int_ior": coat.eta,
            "ext_ior": 1.0,
            "diffuse_reflectance": _rgb(base.albedo),
            "nonlinear": False,
        }
        if coat.roughness > 0:
            out.update(distribution="ggx", alpha=coat.roughness)
        return out
    if isinstance(base, FitMaterial):
        with open(base.file, encoding="utf-8") as f:
            fit = json.load(f)
        p = fit["parameters"]
        if fit.get("model") != "ggx+lambert":
            raise ValueError(f"{where}: a stand-in needs a ggx+lambert fit, not {fit.get('model')}")
        f0 = (p["f0_r"] + p["f0_g"] + p["f0_b"]) / 3
        return {
            "type": "principled",
            "base_color": _rgb([min(max(p[f"rho_{c}"] * base.scale, 0.0), 1.0) for c in "rgb"]),
            "roughness": math.sqrt(p["alpha"]),
            "metallic": 0.0,
            "specular": min(f0 / 0.08, 1.0),  # Mitsuba's F0 = 0.08 x specular
            "clearcoat": 1.0,
            "clearcoat_gloss": 1.0 - coat.roughness,
        }
    raise ValueError(f"{where}: no Mitsuba stand-in for a car paint over a {base.type} base")


def triangle_spheres(scene: Scene) -> Scene:
    """The scene with every analytic sphere tessellated again (Patina's default triangles)."""
    shapes = tuple(dataclasses.replace(s, analytic=False) if isinstance(s, SphereShape) else s for s in scene.shapes)
    return dataclasses.replace(scene, shapes=shapes)


def mitsuba_scene_dict(scene: Scene, variant: str, analytic: bool = False) -> dict[str, Any]:
    """The scene for `mi.load_dict` with Patina's own triangles for every shape (analytic: spheres
    and planes as Mitsuba's analytic shapes instead; a sphere Patina traces analytically is
    always Mitsuba's analytic one) and stand-ins for its car paints."""

    def exact(s: Shape) -> bool:
        return (analytic and s.type in ("sphere", "plane")) or (isinstance(s, SphereShape) and s.analytic)

    meshes = {i: shape_mesh(s) for i, s in enumerate(scene.shapes) if not exact(s)}
    bsdfs = {
        name: stand_in_bsdf(m, f"materials.{name}")
        for name, m in scene.materials.items()
        if isinstance(m, CarpaintMaterial)
    }
    return to_mitsuba(scene, meshes, variant=variant, bsdfs=bsdfs)
