"""The preview scene (patina.scene.preview): the material a file previews as; an RGL .bsdf
as the native RGL material, a Zemax .bsdf (text, same extension) as a table."""

from __future__ import annotations

from patina.scene.preview import material_type, preview_scene_dict
from rgl_tables import write_glossy_rgl


def test_an_rgl_file_previews_as_the_native_rgl_material(tmp_path):
    rgl = write_glossy_rgl(str(tmp_path / "glossy.bsdf"))
    zemax = tmp_path / "zemax.bsdf"
    zemax.write_text("Source  Measured\nSymmetry  PlaneSymmetrical\nScatterType  BRDF\n")
    assert material_type(rgl) == "rgl"
    assert material_type(str(zemax)) == "table"
    assert material_type("fit.json") == "fit"
    assert material_type(str(tmp_path / "missing.bsdf")) == "table"  # the scene reader says it is missing
    scene = preview_scene_dict(rgl, "studio.exr", "sphere", coat=True)
    assert scene["materials"]["material"]["base"] == {"type": "rgl", "file": rgl}
