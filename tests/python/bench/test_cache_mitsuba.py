"""The cache scenes' analytic counterparts for the comparison with Mitsuba 3: tables and fits
become their Lambert fits (the car paint keeps its coat), the result converts to Mitsuba,
and a scene with a light Mitsuba lacks says so."""

from __future__ import annotations

import numpy as np
import pytest

from patina.bench.cache import SCENES
from patina.bench.cache_mitsuba import analytic_counterpart, lambert_fit, mitsuba_dict
from patina.bundled import materials_path
from patina.scene.reading import load_scene
from patina.scene.types import CarpaintMaterial, LambertMaterial, TableMaterial


def test_tables_become_their_lambert_fits_and_the_car_paint_keeps_its_coat():
    scene = load_scene(materials_path("scenes", "cache-room.json"))
    counterpart = analytic_counterpart(scene)
    assert counterpart.shapes == scene.shapes and counterpart.lights == scene.lights
    for name, m in scene.materials.items():
        c = counterpart.materials[name]
        if isinstance(m, TableMaterial):
            assert isinstance(c, LambertMaterial) and c.two_sided == m.two_sided
            assert all(0 <= a <= 1 for a in c.albedo)
        elif isinstance(m, CarpaintMaterial):
            assert isinstance(c, CarpaintMaterial) and isinstance(c.base, LambertMaterial) and c.coat == m.coat
        else:
            assert c == m
    # the red plastic's fit is red, and its tint scales it
    wall = counterpart.materials["feature-wall"].albedo
    assert wall[0] > 3 * wall[1] > 0
    tinted = lambert_fit(scene.materials["plastic"], False).albedo
    assert np.allclose(np.array(tinted) / np.array(wall), [1.2, 6, 9], rtol=1e-4)


def test_the_counterparts_convert_to_mitsuba():
    pytest.importorskip("mitsuba")
    for name in SCENES:
        scene = analytic_counterpart(load_scene(materials_path("scenes", f"{name}.json")))
        converted = mitsuba_dict(scene, variant="scalar_rgb")
        assert converted["type"] == "scene"
        # the interior's four downlights are Mitsuba spots projecting their tables
        assert sum(v.get("type") == "spot" for v in converted.values() if isinstance(v, dict)) == (
            4 if name == "cache-ies-interior" else 0
        )
