"""The one-lobe "principled" parameters OpenPBR, Standard Surface, glTF, USD's preview surface,
Blender's Principled BSDF and pbrt-v4's materials share, from an AnalyticMaterial with at
most one GGX lobe (patina.export.refit brings others to that).

roughness = sqrt(alpha) (each of these squares its roughness into the GGX alpha; pbrt is
given alpha itself with remapping off). A lobe whose mean f0 is at or above METAL_F0 is a
metal: metalness 1 and base colour f0 (their metals are Schlick-like of base colour), the
diffuse dropped. Otherwise a dielectric specular layer over the diffuse base: its index
from the largest channel's f0, ior = (1 + sqrt(f0)) / (1 - sqrt(f0)), and the colour of f0
as a specular tint f0 / F0(ior), so that the tint stays within [0, 1]. The coat is coat
weight 1 at its roughness and index."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from patina.export.material import RGB, AnalyticMaterial

METAL_F0 = 0.25  # mean f0 from which a lobe is written as a metal (dielectrics stay below about 0.1)


def ior_from_f0(f0: float) -> float:
    r = math.sqrt(min(max(f0, 1e-6), 0.99))
    return (1 + r) / (1 - r)


def f0_from_ior(ior: float) -> float:
    return ((ior - 1) / (ior + 1)) ** 2


@dataclass
class Principled:
    base_color: RGB
    metalness: float
    specular_weight: float
    specular_color: RGB
    specular_ior: float
    specular_roughness: float
    coat_weight: float
    coat_roughness: float
    coat_ior: float
    notes: list[str] = field(default_factory=list)


def principled(material: AnalyticMaterial) -> Principled:
    if len(material.lobes) > 1 or (material.lobes and material.distribution != "ggx"):
        raise ValueError("principled targets hold one GGX lobe: refit first")
    notes: list[str] = []
    base = tuple(min(max(c, 0.0), 1.0) for c in material.diffuse)
    metal, weight, tint, ior, roughness = 0.0, 0.0, (1.0, 1.0, 1.0), 1.5, 0.5
    if material.lobes:
        lobe = material.lobes[0]
        roughness = math.sqrt(lobe.alpha)
        mean = sum(lobe.f0) / 3
        if mean >= METAL_F0:
            metal, weight, base = 1.0, 1.0, tuple(min(max(c, 0.0), 1.0) for c in lobe.f0)
            if max(material.diffuse) > 0.01:
                notes.append(
                    "metal lobe (mean f0 >= 0.25): the diffuse albedo is dropped, these targets' metals have none"
                )
        else:
            weight, ior = 1.0, ior_from_f0(max(lobe.f0))
            tint = tuple(min(max(f, 0.0) / f0_from_ior(ior), 1.0) for f in lobe.f0)
    coat = material.coat
    return Principled(
        base_color=base,
        metalness=metal,
        specular_weight=weight,
        specular_color=tint,
        specular_ior=ior,
        specular_roughness=roughness,
        coat_weight=1.0 if coat else 0.0,
        coat_roughness=math.sqrt(coat.alpha) if coat else 0.0,
        coat_ior=coat.eta if coat else 1.5,
        notes=notes,
    )
