"""Blender: a Python script that builds the material as a Principled BSDF node tree (Blender
4.x input names; Blender's roughness is squared into the GGX alpha, as the others' are). Run
it in Blender's Python console, with `blender --python FILE`, or under the `bpy` module."""

from __future__ import annotations

from patina.export.material import AnalyticMaterial
from patina.export.principled import principled

TEMPLATE = '''"""{name}: exported by patina export from {source} ({model}). Builds the material in Blender."""
import bpy

material = bpy.data.materials.get({name!r}) or bpy.data.materials.new({name!r})
material.use_nodes = True
material.use_backface_culling = {backface}
nodes = material.node_tree.nodes
bsdf = nodes.get("Principled BSDF") or nodes.new("ShaderNodeBsdfPrincipled")
values = {values!r}
for key, value in values.items():
    bsdf.inputs[key].default_value = value
'''


def blender_inputs(material: AnalyticMaterial, notes: list[str] | None = None) -> dict[str, object]:
    p = principled(material)
    if notes is not None:
        notes.extend(p.notes)
    return {
        "Base Color": (*p.base_color, 1.0),
        "Metallic": p.metalness,
        "Roughness": p.specular_roughness,
        "IOR": p.specular_ior,
        "Specular IOR Level": 0.5 * p.specular_weight,  # 0.5: the IOR's own F0
        "Specular Tint": (*p.specular_color, 1.0),
        "Coat Weight": p.coat_weight,
        "Coat Roughness": p.coat_roughness,
        "Coat IOR": p.coat_ior,
    }


def to_blender_script(material: AnalyticMaterial, notes: list[str] | None = None) -> str:
    values = {
        k: (tuple(round(float(x), 6) for x in v) if isinstance(v, tuple) else round(float(v), 6))
        for k, v in blender_inputs(material, notes).items()
    }
    return TEMPLATE.format(
        name=material.name, source=material.source, model=material.model, backface=not material.two_sided, values=values
    )
