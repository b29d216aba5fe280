"""The bench's scenes as Mitsuba renders them: the stand-in BSDFs of the coated materials, and
the preview-mitsuba scene rendering (Mitsuba scalar_rgb, tiny) to nearly Patina's image mean."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patina.bench.mitsuba_scenes import mitsuba_scene_dict, preview_mitsuba_scene, stand_in_bsdf
from patina.render.run import PreparedScene, render
from patina.scene.reading import with_overrides
from patina.scene.types import TableMaterial

mi = pytest.importorskip("mitsuba")


def test_stand_ins_follow_the_structure_of_each_coat():
    scene = preview_mitsuba_scene(16, 12)
    plastic = stand_in_bsdf(scene.materials["plastic"], "materials.plastic")
    assert plastic["type"] == "roughplastic" and plastic["alpha"] == pytest.approx(0.1)
    assert plastic["int_ior"] == pytest.approx(1.5)
    assert plastic["diffuse_reflectance"]["value"] == pytest.approx([0.6, 0.12, 0.08])
    paint = stand_in_bsdf(scene.materials["paint"], "materials.paint")
    assert paint["type"] == "principled" and paint["clearcoat"] == 1.0
    assert 0 < paint["roughness"] < 1 and 0 < paint["specular"] <= 1
    table_base = dataclasses.replace(
        scene.materials["paint"], base=TableMaterial(file="x.ptab", scale=1.0, tint=(1, 1, 1), two_sided=False)
    )
    with pytest.raises(ValueError, match=r"materials\.paint: no Mitsuba stand-in"):
        stand_in_bsdf(table_base, "materials.paint")


def test_preview_mitsuba_renders_near_patinas_image():
    scene = with_overrides(preview_mitsuba_scene(24, 18), spp=64)
    ours = render(scene, prepared=PreparedScene(scene), progress=False).rgb
    d = mitsuba_scene_dict(scene, "scalar_rgb")
    assert {k for k in d if k.startswith("shape_")} == {f"shape_{i}" for i in range(len(scene.shapes))}
    theirs = np.asarray(mi.render(mi.load_dict(d), spp=64))
    assert theirs.shape == ours.shape
    # the same scene up to the stand-ins' few percent (and 64 spp of noise on 432 pixels)
    assert float(ours.mean()) / float(theirs.mean()) == pytest.approx(1.0, abs=0.12)


def test_the_gold_sphere_is_analytic_on_both_sides_and_triangles_on_both_for_its_triangles_record():
    from patina.bench.mitsuba_scenes import triangle_spheres
    from patina.bundled import materials_path
    from patina.scene.reading import load_scene

    scene = with_overrides(load_scene(materials_path("scenes", "conductor-sphere.json")), width=16, height=12)
    assert [s.analytic for s in scene.shapes] == [True]
    exact = mitsuba_scene_dict(scene, "scalar_rgb")
    assert exact["shape_0"]["type"] == "sphere"  # a dict: Mitsuba's analytic sphere
    tri = triangle_spheres(scene)
    assert [s.analytic for s in tri.shapes] == [False] and tri.materials == scene.materials
    assert PreparedScene(tri).triangles > 10000 and PreparedScene(scene).triangles == 0
    assert not isinstance(mitsuba_scene_dict(tri, "scalar_rgb")["shape_0"], dict)  # a mi.Mesh of the triangles
