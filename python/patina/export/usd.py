"""USD: a layer with the material as a UsdPreviewSurface (usd-core; a dielectric lobe in its
specular workflow, specularColor = f0, a metal in its metallic one) and, beside it under the
`mtlx` render context, the same OpenPBR Surface the MaterialX export writes
(ND_open_pbr_surface_surfaceshader), on a preview sphere bound to it."""

from __future__ import annotations

from patina.export.material import AnalyticMaterial
from patina.export.materialx import _inputs
from patina.export.principled import principled

OPENPBR_ID = "ND_open_pbr_surface_surfaceshader"


def write_usd(material: AnalyticMaterial, path: str, notes: list[str] | None = None) -> None:
    """Writes the layer (.usda text, .usd or .usdc binary by the extension) to `path` as given."""
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdShade

    p = principled(material)
    if notes is not None:
        notes.extend(p.notes)
    stage = Usd.Stage.CreateNew(path)
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    root = UsdGeom.Xform.Define(stage, "/Patina")
    stage.SetDefaultPrim(root.GetPrim())
    mat = UsdShade.Material.Define(stage, f"/Patina/Materials/{material.name}")
    preview = UsdShade.Shader.Define(stage, mat.GetPath().AppendChild("PreviewSurface"))
    preview.CreateIdAttr("UsdPreviewSurface")
    inputs = {
        "diffuseColor": (Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*p.base_color)),
        "metallic": (Sdf.ValueTypeNames.Float, p.metalness),
        "roughness": (Sdf.ValueTypeNames.Float, p.specular_roughness),
        "ior": (Sdf.ValueTypeNames.Float, p.specular_ior),
        "clearcoat": (Sdf.ValueTypeNames.Float, p.coat_weight),
        "clearcoatRoughness": (Sdf.ValueTypeNames.Float, p.coat_roughness),
    }
    if p.specular_weight and not p.metalness:  # f0 itself, colour and all
        f0 = material.lobes[0].f0
        inputs["useSpecularWorkflow"] = (Sdf.ValueTypeNames.Int, 1)
        inputs["specularColor"] = (Sdf.ValueTypeNames.Color3f, Gf.Vec3f(*[min(max(c, 0.0), 1.0) for c in f0]))
    for name, (kind, value) in inputs.items():
        preview.CreateInput(name, kind).Set(value)
    mat.CreateSurfaceOutput().ConnectToSource(preview.ConnectableAPI(), "surface")
    openpbr = UsdShade.Shader.Define(stage, mat.GetPath().AppendChild("OpenPBRSurface"))
    openpbr.CreateIdAttr(OPENPBR_ID)
    for name, value in _inputs(p).items():
        if isinstance(value, tuple):
            openpbr.CreateInput(name, Sdf.ValueTypeNames.Color3f).Set(Gf.Vec3f(*value))
        else:
            openpbr.CreateInput(name, Sdf.ValueTypeNames.Float).Set(float(value))
    mat.CreateSurfaceOutput("mtlx").ConnectToSource(openpbr.ConnectableAPI(), "surface")
    ball = UsdGeom.Sphere.Define(stage, "/Patina/PreviewSphere")
    ball.CreateDoubleSidedAttr(material.two_sided)
    UsdShade.MaterialBindingAPI.Apply(ball.GetPrim()).Bind(mat)
    stage.GetRootLayer().Save()
