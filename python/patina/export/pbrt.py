"""pbrt-v4: a scene-file `MakeNamedMaterial` block, roughness given as alpha with
`remaproughness` false. Lambert alone is `diffuse`; a metal lobe (mean f0 >= 0.25) is
`conductor` with its f0 as `reflectance`; Lambert + a dielectric lobe is `coateddiffuse`
(the lobe as the interface: its index from f0, its alpha); a clear coat over Lambert is
`coateddiffuse` with the coat's index and alpha (a dielectric lobe under it is dropped:
noted), over a metal lobe `coatedconductor`. pbrt's coated materials are stochastic layers:
the light between coat and base is simulated, not the single scattering Patina fits."""

from __future__ import annotations

from patina.export.material import AnalyticMaterial
from patina.export.principled import METAL_F0, ior_from_f0


def _rgb(values) -> str:
    return "[ " + " ".join(f"{float(v):.6g}" for v in values) + " ]"


def to_pbrt(material: AnalyticMaterial, notes: list[str] | None = None) -> str:
    notes = notes if notes is not None else []
    if len(material.lobes) > 1 or (material.lobes and material.distribution != "ggx"):
        raise ValueError("pbrt-v4 materials hold one GGX lobe: refit first")
    lobe = material.lobes[0] if material.lobes else None
    coat = material.coat
    metal = lobe is not None and sum(lobe.f0) / 3 >= METAL_F0
    lines: list[tuple[str, str, str]] = []  # (type name, parameter, value)
    if metal and coat:
        kind = "coatedconductor"
        lines += [("float", "interface.roughness", f"{coat.alpha:.6g}"), ("float", "interface.eta", f"{coat.eta:.6g}")]
        lines += [("float", "conductor.roughness", f"{lobe.alpha:.6g}"), ("rgb", "reflectance", _rgb(lobe.f0))]
    elif metal:
        kind = "conductor"
        lines += [("float", "roughness", f"{lobe.alpha:.6g}"), ("rgb", "reflectance", _rgb(lobe.f0))]
    elif coat or lobe:
        kind = "coateddiffuse"
        alpha, eta = (coat.alpha, coat.eta) if coat else (lobe.alpha, ior_from_f0(sum(lobe.f0) / 3))
        if coat and lobe:
            notes.append("pbrt: the dielectric lobe under the coat is dropped (coateddiffuse has one interface)")
        lines += [("rgb", "reflectance", _rgb(material.diffuse)), ("float", "roughness", f"{alpha:.6g}")]
        lines += [("float", "eta", f"{eta:.6g}")]
    else:
        kind = "diffuse"
        lines += [("rgb", "reflectance", _rgb(material.diffuse))]
    if metal and max(material.diffuse) > 0.01:
        notes.append("pbrt: a metal lobe's diffuse albedo is dropped (conductors have none)")
    if kind != "diffuse":
        lines.append(("bool", "remaproughness", "false"))
    body = "\n".join(f'    "{t} {name}" {value}' for t, name, value in lines)
    header = f"# {material.name}: exported by patina export from {material.source} ({material.model})\n"
    return header + f'MakeNamedMaterial "{material.name}"\n    "string type" "{kind}"\n{body}\n'
