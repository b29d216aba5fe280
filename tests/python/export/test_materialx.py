"""MaterialX export: the document passes MaterialX's validate(), and its inputs read back give
the material's parameters (alpha, f0 through the index and tint, the coat)."""

from __future__ import annotations

import pytest

from export_helpers import COATED, GGX, METAL
from patina.export.materialx import to_materialx
from patina.export.principled import f0_from_ior

mx = pytest.importorskip("MaterialX")


def _read(text: str):
    doc = mx.createDocument()
    mx.readFromXmlString(doc, text)
    return doc


def _shader_inputs(text: str, category: str) -> dict:
    doc = _read(text)
    libs = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), libs)
    doc.importLibrary(libs)
    valid, message = doc.validate()
    assert valid, message
    (shader,) = [n for n in doc.getNodes() if n.getCategory() == category]
    return {i.getName(): i.getValue() for i in shader.getInputs()}


def test_openpbr_document_validates_and_round_trips():
    values = _shader_inputs(to_materialx(COATED), "open_pbr_surface")
    lobe = COATED.lobes[0]
    assert values["specular_roughness"] ** 2 == pytest.approx(lobe.alpha, rel=1e-5)
    f0 = [f0_from_ior(values["specular_ior"]) * c for c in values["specular_color"]]
    assert f0 == pytest.approx(list(lobe.f0), rel=1e-4)
    assert list(values["base_color"]) == pytest.approx(list(COATED.diffuse), rel=1e-5)
    assert values["coat_weight"] == 1 and values["coat_ior"] == pytest.approx(COATED.coat.eta)
    assert values["coat_roughness"] ** 2 == pytest.approx(COATED.coat.alpha, rel=1e-5)


def test_standard_surface_on_request():
    values = _shader_inputs(to_materialx(GGX, "standard_surface"), "standard_surface")
    assert values["specular_roughness"] ** 2 == pytest.approx(GGX.lobes[0].alpha, rel=1e-5)
    assert values["metalness"] == 0 and values["coat"] == 0


def test_metal_lobe_becomes_metalness_with_f0_as_base_colour():
    values = _shader_inputs(to_materialx(METAL), "open_pbr_surface")
    assert values["base_metalness"] == 1
    assert list(values["base_color"]) == pytest.approx(list(METAL.lobes[0].f0), rel=1e-5)
