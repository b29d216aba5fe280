"""USD export: usd-core opens the layer, finds the preview surface's and OpenPBR's inputs, and
they give the material's parameters back."""

from __future__ import annotations

import pytest

from export_helpers import COATED
from patina.export.principled import f0_from_ior
from patina.export.usd import OPENPBR_ID, write_usd

pxr = pytest.importorskip("pxr")


def test_layer_opens_with_both_shaders_and_their_inputs(tmp_path):
    from pxr import Usd, UsdShade

    path = tmp_path / "m.usda"
    write_usd(COATED, str(path))
    stage = Usd.Stage.Open(str(path))
    material = UsdShade.Material(stage.GetPrimAtPath("/Patina/Materials/coated"))
    preview = UsdShade.Shader(stage.GetPrimAtPath("/Patina/Materials/coated/PreviewSurface"))
    assert preview.GetIdAttr().Get() == "UsdPreviewSurface"
    lobe = COATED.lobes[0]
    assert preview.GetInput("roughness").Get() ** 2 == pytest.approx(lobe.alpha, rel=1e-5)
    assert preview.GetInput("useSpecularWorkflow").Get() == 1
    assert list(preview.GetInput("specularColor").Get()) == pytest.approx(list(lobe.f0), rel=1e-6)
    assert f0_from_ior(preview.GetInput("ior").Get()) == pytest.approx(max(lobe.f0), rel=1e-4)
    assert preview.GetInput("clearcoatRoughness").Get() ** 2 == pytest.approx(COATED.coat.alpha, rel=1e-5)
    assert list(preview.GetInput("diffuseColor").Get()) == pytest.approx(list(COATED.diffuse), rel=1e-6)
    openpbr = UsdShade.Shader(stage.GetPrimAtPath("/Patina/Materials/coated/OpenPBRSurface"))
    assert openpbr.GetIdAttr().Get() == OPENPBR_ID
    assert openpbr.GetInput("coat_ior").Get() == pytest.approx(COATED.coat.eta)
    assert material.GetSurfaceOutput("mtlx").HasConnectedSource()
    bound = UsdShade.MaterialBindingAPI(stage.GetPrimAtPath("/Patina/PreviewSphere")).ComputeBoundMaterial()[0]
    assert bound.GetPath() == material.GetPath()
