"""The scene handed to C++: materials, lights and the camera cross as dictionaries of exactly
the keys the renderer reads, so a misspelled, unused or missing key is an error naming the
key and its material or light (never a silent default); the light data derived from the
geometry (quad normal and area, the sun's cone and frame, an emissive mesh's area cdf) is
computed in patina.render.prepare and matches an independent numpy computation; every
bundled scene still prepares."""

from __future__ import annotations

import glob
import math
import os

import numpy as np
import pytest

from patina.errors import FormatError
from patina.native import _core
from patina.render.prepare import (
    PreparedScene,
    core_camera,
    orthonormal_frame32,
    quad_normal_area,
    sun_cone,
    triangle_area_cdf,
    unit_vector32,
)
from patina.scene.reading import load_scene, parse_scene
from repo_paths import ROOT

TORUS = os.path.join(ROOT, "materials", "samples", "torus.obj")
STREETLIGHT = os.path.join(ROOT, "materials", "luminaires", "streetlight.ies")
TORUS_PLACED = {"scale": [0.2, 0.3, 0.2], "translate": [0, 1.6, -0.5]}


def scene_obj(lights: list, materials: dict | None = None) -> dict:
    return {
        "version": 1,
        "camera": {"position": [0, 1, 3.9], "look_at": [0, 1, 0], "fov": 40, "width": 16, "height": 12},
        "render": {"spp": 1, "integrator": "path", "max_depth": 2, "seed": 0},
        "materials": materials or {"white": {"type": "lambert", "albedo": 0.7}},
        "shapes": [{"type": "plane", "material": next(iter(materials or {"white": 0})), "size": [4, 4]}],
        "lights": lights,
    }


EVERY_LIGHT = [
    {"type": "point", "position": [0, 2, 0], "intensity": 3},
    {"type": "spot", "position": [0, 2, 1], "direction": [0, -1, -0.3], "intensity": 4, "outer_angle": 35},
    {"type": "sun", "direction": [0.3, 0.8, 0.5], "angular_diameter": 2.0, "irradiance": 3},
    {"type": "quad", "center": [0, 2.2, 0], "u": [0.25, 0, 0.05], "v": [0, 0, 0.25], "radiance": 6},
    {"type": "disk", "center": [0.8, 1.8, 0], "normal": [0, -1, 0], "radius": 0.2, "radiance": 5},
    {"type": "sphere", "center": [-1, 1.5, 0.5], "radius": 0.1, "radiance": 8},
    {"type": "mesh", "file": TORUS, "transform": TORUS_PLACED, "radiance": 2},
    {"type": "luminaire", "file": STREETLIGHT, "position": [0, 3, 0]},
]


@pytest.fixture(scope="module")
def prepared() -> PreparedScene:
    return PreparedScene(parse_scene(scene_obj(EVERY_LIGHT), os.path.join(ROOT, "lights.json")))


# --- every key checked ---------------------------------------------------------------


def lambert(**extra) -> dict:
    return {"kind": "lambert", "albedo": [0.5, 0.5, 0.5], "two_sided": False, "coat": False, **extra}


def point(**extra) -> dict:
    return {"kind": "point", "position": [0.0, 1.0, 0.0], "power": [1.0, 1.0, 1.0], **extra}


def test_a_misspelled_material_key_is_an_error_naming_it_and_the_material(prepared):
    n = len(prepared.core_materials)
    d = lambert()
    d["albdo"] = d.pop("albedo")
    with pytest.raises(ValueError, match=rf"material {n} \(lambert\): missing key 'albedo'"):
        prepared.core.add_material(d)
    with pytest.raises(ValueError, match=rf"material {n} \(lambert\): unknown key 'albdo' \(the renderer reads "):
        prepared.core.add_material(lambert(albdo=[0.1, 0.2, 0.3]))


def test_a_misspelled_light_key_is_an_error_naming_it_and_the_light(prepared):
    n = len(prepared.core_lights)
    with pytest.raises(ValueError, match=rf"light {n} \(point\): unknown key 'positon'"):
        prepared.core.add_light(point(positon=[0.0, 2.0, 0.0]))
    d = point()
    del d["position"]
    with pytest.raises(ValueError, match=rf"light {n} \(point\): missing key 'position'"):
        prepared.core.add_light(d)


@pytest.mark.parametrize(
    ("where", "edit"),
    [
        ("materials.white.albdo", lambda o: o["materials"]["white"].update(albdo=0.5)),
        ("lights[0].two_side", lambda o: o["lights"][0].update(two_side=True)),
    ],
)
def test_a_misspelled_key_in_a_scene_file_is_an_error_naming_it(where, edit):
    obj = scene_obj([dict(EVERY_LIGHT[3])])
    edit(obj)
    with pytest.raises(FormatError) as e:
        parse_scene(obj, os.path.join(ROOT, "s.json"))
    assert e.value.where == where and "unknown key" in str(e.value)


@pytest.mark.parametrize(
    ("material", "key"),
    [
        (lambert(tint=[1.0, 1.0, 1.0]), "tint"),  # a Lambert is not tinted
        (lambert(coat_eta=1.5), "coat_eta"),  # a coat's values without the coat
        ({"kind": "emitter", "light": 0, "two_sided": True}, "two_sided"),  # the light's, not the emitter's
        ({"kind": "dielectric", "alpha_x": 0.1, "alpha_y": 0.1, "eta": [1.5] * 3, "albedo": [1.0] * 3}, "alpha_y"),
    ],
)
def test_a_key_the_renderer_does_not_read_for_that_kind_is_an_error(prepared, material, key):
    with pytest.raises(ValueError, match=f"unknown key '{key}'"):
        prepared.core.add_material(material)


def test_a_light_key_of_another_kind_is_an_error(prepared):
    with pytest.raises(ValueError, match=r"\(point\): unknown key 'two_sided'"):
        prepared.core.add_light(point(two_sided=True))
    with pytest.raises(ValueError, match=r"\(spot\): missing key 'direction'"):
        prepared.core.add_light(point(kind="spot", cos_inner=1.0, cos_outer=0.5))


def test_every_value_is_required_none_takes_a_default(prepared):
    for key in ("two_sided", "coat"):
        d = lambert()
        del d[key]
        with pytest.raises(ValueError, match=f"missing key '{key}'"):
            prepared.core.add_material(d)
    with pytest.raises(ValueError, match="missing key 'coat_tint'"):
        prepared.core.add_material(lambert(coat=True, coat_eta=1.5, coat_alpha=0.0))


def test_wrong_types_and_values_name_the_key(prepared):
    with pytest.raises(ValueError, match="'albedo' must be 3 numbers"):
        prepared.core.add_material(lambert(albedo=[0.5, 0.5]))
    with pytest.raises(ValueError, match="'albedo' is not finite"):
        prepared.core.add_material(lambert(albedo=[0.5, math.nan, 0.5]))
    with pytest.raises(ValueError, match="'two_sided' must be a bool"):
        prepared.core.add_material(lambert(two_sided="yes"))
    with pytest.raises(ValueError, match="unknown material kind 'lambart'"):
        prepared.core.add_material(lambert(kind="lambart"))
    with pytest.raises(ValueError, match="unknown light kind 'pont'"):
        prepared.core.add_light(point(kind="pont"))


def test_the_camera_fields_are_checked_too(prepared):
    cam = core_camera(prepared.scene)
    args = (prepared.accel, *prepared.arrays)
    with pytest.raises(TypeError, match="Camera: no field 'fov'"):
        _core.Camera(fov=40)
    with pytest.raises(ValueError, match=r"Camera\.position: must be 3 numbers"):
        cam.position = [0.0, 1.0]
    cam.focus_distance = math.inf
    with pytest.raises(ValueError, match="the camera: 'focus_distance' is not finite"):
        type(prepared.core)(*args, cam)


def light_entry(prepared: PreparedScene, kind: str) -> dict:
    return dict(next(d for d in prepared.core_lights if d["kind"] == kind))


def test_derived_light_data_is_checked_not_computed(prepared):
    quad = light_entry(prepared, "quad")
    with pytest.raises(ValueError, match=r"\(quad\): 'normal' must be a unit vector"):
        prepared.core.add_light(dict(quad, normal=[0.0, 2.0, 0.0]))
    with pytest.raises(ValueError, match=r"\(quad\): 'area' must be > 0"):
        prepared.core.add_light(dict(quad, area=0.0))
    tri = light_entry(prepared, "triangles")
    cdf = tri["area_cdf"].copy()
    cdf[-1] = 0.999
    with pytest.raises(ValueError, match="'area_cdf' must go from 0 to exactly 1"):
        prepared.core.add_light(dict(tri, area_cdf=cdf))
    cdf = tri["area_cdf"].copy()
    cdf[1], cdf[2] = cdf[2], cdf[1]
    with pytest.raises(ValueError, match="'area_cdf' must not decrease"):
        prepared.core.add_light(dict(tri, area_cdf=cdf))
    with pytest.raises(ValueError, match="one value per triangle"):
        prepared.core.add_light(dict(tri, area_cdf=tri["area_cdf"][:-1]))
    with pytest.raises(ValueError, match="out of range"):
        prepared.core.add_light(dict(tri, triangles=tri["triangles"] + prepared.triangles))
    sun = light_entry(prepared, "sun")
    with pytest.raises(ValueError, match="the sun's disc"):
        prepared.core.add_light(dict(sun, sun_one_minus_cos=0.5))


# --- the derived light data against numpy ------------------------------------------------


def test_quad_normal_and_area_match_numpy():
    rng = np.random.default_rng(1)
    for _ in range(50):
        u, v = rng.normal(size=3), rng.normal(size=3)
        normal, area = quad_normal_area(u, v)
        c = np.cross(u.astype(np.float32).astype(np.float64), v.astype(np.float32).astype(np.float64))
        np.testing.assert_allclose(normal, c / np.linalg.norm(c), rtol=0, atol=1e-6)
        np.testing.assert_allclose(area, 4 * np.linalg.norm(c), rtol=1e-6)
    with pytest.raises(ValueError, match="non-parallel"):
        quad_normal_area([1, 0, 0], [2, 0, 0])


def test_sun_cone_and_frame_match_numpy():
    for degrees in (0.01, 0.265, 1.0, 10.0):
        half = math.radians(degrees)
        cos_sun, one_minus = sun_cone(half)
        assert cos_sun == pytest.approx(np.cos(half), abs=1e-7)
        assert one_minus == pytest.approx(1 - np.cos(np.float64(half)), rel=1e-6)  # no cancellation
    rng = np.random.default_rng(2)
    for n in [*rng.normal(size=(50, 3)), [0, 0, -1], [0, 0, 1], [1, 0, 0]]:
        d = np.asarray(unit_vector32(n))
        np.testing.assert_allclose(d, np.asarray(n) / np.linalg.norm(n), atol=1e-6)
        t, b = (np.asarray(x) for x in orthonormal_frame32(d))
        frame = np.stack([t, b, d])
        np.testing.assert_allclose(frame @ frame.T, np.eye(3), atol=1e-6)
        np.testing.assert_allclose(np.cross(t, b), d, atol=1e-6)  # right-handed around d


def test_triangle_area_cdf_matches_numpy():
    rng = np.random.default_rng(3)
    v = rng.normal(size=(40, 3))
    f = rng.integers(0, 40, size=(60, 3))
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])]
    cdf, total = triangle_area_cdf(v, f)
    p = v.astype(np.float32).astype(np.float64)[f]
    areas = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    assert cdf.dtype == np.float32 and cdf.shape == (len(f) + 1,)
    assert cdf[0] == 0 and cdf[-1] == 1 and (np.diff(cdf) >= 0).all()
    np.testing.assert_allclose(cdf[1:], np.cumsum(areas) / areas.sum(), atol=1e-6)
    assert total == pytest.approx(areas.sum(), rel=1e-6)
    with pytest.raises(ValueError, match="positive area"):
        triangle_area_cdf(np.zeros((3, 3)), np.array([[0, 1, 2]]))


def test_the_prepared_lights_carry_the_derived_data(prepared):
    scene = prepared.scene
    quad = light_entry(prepared, "quad")
    ql = next(li for li in scene.lights if li.type == "quad")
    c = np.cross(ql.u, ql.v)
    np.testing.assert_allclose(quad["normal"], c / np.linalg.norm(c), atol=1e-6)
    assert quad["area"] == pytest.approx(4 * np.linalg.norm(c), rel=1e-6)
    sun = light_entry(prepared, "sun")
    assert sun["cos_sun"] == pytest.approx(math.cos(math.radians(1.0)), abs=1e-7)
    # the disk's fan: DISK_SEGMENTS equal triangles of total area pi r^2
    disk = next(d for d in prepared.core_lights if d["kind"] == "triangles")
    np.testing.assert_allclose(np.diff(disk["area_cdf"]), 1 / len(disk["triangles"]), atol=1e-6)
    assert disk["area"] == pytest.approx(math.pi * 0.2**2, rel=1e-5)


# --- every bundled scene, and every kind of light, still prepares ------------------------


@pytest.mark.parametrize("path", sorted(glob.glob(os.path.join(ROOT, "materials", "scenes", "*.json"))))
def test_every_bundled_scene_prepares(path):
    p = PreparedScene(load_scene(path))
    assert len(p.core_materials) >= len(p.scene.materials)
    assert len(p.core_lights) == len(p.scene.lights)


def test_every_kind_of_light_prepares(prepared):
    kinds = [d["kind"] for d in prepared.core_lights]
    assert kinds == ["point", "spot", "sun", "quad", "triangles", "triangles", "triangles", "goniometric"]
