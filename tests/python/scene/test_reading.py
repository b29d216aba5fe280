"""Scene files: the documented examples parse, defaults and conventions hold, every error names
its key path, and no mutation of a valid scene raises anything but FormatError."""

from __future__ import annotations

import copy
import glob
import json
import math
import os
import shutil

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patina.errors import FormatError
from patina.scene import load_scene, parse_scene, scene_to_json, with_overrides
from patina.scene.metals import METALS
from patina.scene.types import MapEnvironment
from scene_helpers import ROOT, doc_blocks, write_stand_ins

DOC_SCENES = doc_blocks("json")
FULL = {
    "version": 1,
    "camera": {"type": "thinlens", "position": [0, 1, 5], "look_at": [0, 0.5, 0], "up": [0, 1, 0.1], "fov": 40,
               "width": 64, "height": 48, "aperture_radius": 0.02, "focus_distance": 4.5},
    "render": {"spp": 4, "integrator": "path", "max_depth": 5, "seed": 3},
    "materials": {
        "t": {"type": "table", "file": "a.ptab", "scale": 2, "tint": [1, 0.5, 0.5], "two_sided": True},
        "f": {"type": "fit", "file": "fit.json"},
        "l": {"type": "lambert", "albedo": 0.25},
        "c": {"type": "conductor", "eta": [0.2, 0.3, 1.5], "k": [3, 2.7, 1.9], "roughness": [0.1, 0.3]},
        "au": {"type": "conductor", "metal": "Au", "roughness": 0.2, "tint": 0.9},
        "d": {"type": "dielectric", "eta": 1.33, "roughness": 0.05},
        "paint": {"type": "carpaint", "base": {"type": "table", "file": "base.ptab"},
                  "coat": {"eta": 1.5, "roughness": 0.02, "thickness_tint": [0.9, 0.95, 1]}, "two_sided": True},
    },
    "shapes": [
        {"type": "sphere", "material": "l", "radius": 0.5, "transform": {"translate": [1, 0, 0]}},
        {"type": "plane", "material": "t", "size": [4, 3], "transform": {"scale": [2, 1, 1]}},
        {"type": "ball", "material": "paint", "transform": {"rotate": [[0, 1, 0], 30]}},
        {"type": "panel", "material": "au", "size": [2, 1],
         "transform": {"rotate": [[[1, 0, 0], 10], [[0, 0, 1], 20]]}},
        {"type": "mesh", "material": "c", "file": "meshes/m.obj",
         "transform": {"matrix": [[1, 0, 0, 1], [0, 2, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}},
        {"type": "sphere", "material": "d"},
        {"type": "sphere", "material": "f"},
    ],
    "lights": [
        {"type": "point", "position": [0, 3, 0], "intensity": [10, 10, 8]},
        {"type": "quad", "center": [0, 2, 0], "u": [0.5, 0, 0], "v": [0, 0, -0.5], "radiance": 5, "two_sided": True},
    ],
    "environment": {"type": "map", "file": "env/studio.exr", "rotation": 45, "intensity": 0.5},
}  # fmt: skip


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> str:
    """A folder holding empty stand-ins for every file the test scenes and the doc examples name."""
    d = str(tmp_path_factory.mktemp("scenes"))
    for obj in [FULL, *(json.loads(b) for b in DOC_SCENES)]:
        write_stand_ins(obj, d)
    os.mkdir(os.path.join(d, "folder.ptab"))
    return d


def parse(obj, folder: str):
    return parse_scene(obj, os.path.join(folder, "scene.json"))


def error(obj, folder: str) -> FormatError:
    with pytest.raises(FormatError) as info:
        parse(obj, folder)
    return info.value


# --- the documentation ---------------------------------------------------------------------


def test_doc_has_examples():
    assert len(DOC_SCENES) >= 4
    assert doc_blocks("jsonc")


@pytest.mark.parametrize("index", range(len(DOC_SCENES)))
def test_doc_example_parses(index, folder):
    scene = parse(json.loads(DOC_SCENES[index]), folder)
    assert scene.camera.width >= 1
    assert all(s.material in scene.materials for s in scene.shapes)


def test_doc_transform_fragments_parse(folder):
    base = json.loads(DOC_SCENES[0])
    for line in doc_blocks("jsonc")[0].strip().splitlines():
        obj = copy.deepcopy(base)
        obj["shapes"][0]["transform"] = json.loads(line)
        m = parse(obj, folder).shapes[0].transform
        assert m.shape == (4, 4) and np.isfinite(m).all()


def test_doc_metal_table_matches_presets():
    text = open(os.path.join(ROOT, "docs", "scene.md"), encoding="utf-8").read()
    for name, (eta, k) in METALS.items():
        row = f"| `{name}` | {', '.join(f'{x:.4f}' for x in eta)} | {', '.join(f'{x:.4f}' for x in k)} |"
        assert row in text


# --- what a parsed scene holds ---------------------------------------------------------------


def test_defaults_filled(folder):
    scene = parse({"version": 1, "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}}, folder)
    c = scene.camera
    assert (c.type, c.up, c.fov, c.width, c.height, c.aperture_radius) == ("pinhole", (0, 1, 0), 30, 640, 480, 0)
    assert c.focus_distance == pytest.approx(3.0)
    r = scene.render
    assert (r.spp, r.integrator, r.max_depth, r.seed) == (64, "direct", 8, 0)
    assert scene.materials == {} and scene.shapes == () and scene.lights == () and scene.environment is None

    obj = copy.deepcopy(FULL)
    obj["materials"] = {"m": {"type": "conductor", "metal": "Cu"}, "l": {"type": "lambert"}}
    obj["shapes"] = [{"type": "sphere", "material": "m"}, {"type": "plane", "material": "l"}]
    scene = parse(obj, folder)
    m = scene.materials["m"]
    assert m.roughness == (0.1, 0.1) and (m.eta, m.k) == METALS["Cu"] and m.tint == (1, 1, 1)
    assert scene.materials["l"].albedo == (0.5, 0.5, 0.5)
    assert scene.shapes[0].radius == 1.0 and scene.shapes[1].size == (2.0, 2.0)
    assert np.array_equal(scene.shapes[0].transform, np.eye(4))


def test_rgl_material_defaults_sampling_and_suffix(tmp_path):
    (tmp_path / "x.bsdf").write_bytes(b"")  # the reader only checks that it exists
    (tmp_path / "x.ptab").write_bytes(b"")
    obj = {"version": 1, "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0]}}
    obj["materials"] = {
        "r": {"type": "rgl", "file": "x.bsdf"},
        "cosine": {"type": "rgl", "file": "x.bsdf", "sampling": "cosine", "tint": 0.5, "two_sided": True},
        "coated": {"type": "carpaint", "base": {"type": "rgl", "file": "x.bsdf"}},
    }
    scene = parse(obj, str(tmp_path))
    r, cosine = scene.materials["r"], scene.materials["cosine"]
    assert (r.type, r.file, r.scale, r.tint, r.two_sided, r.sampling) == (
        "rgl",
        str(tmp_path / "x.bsdf"),
        1.0,
        (1, 1, 1),
        False,
        "file",
    )
    assert (cosine.sampling, cosine.tint, cosine.two_sided) == ("cosine", (0.5, 0.5, 0.5), True)
    assert scene.materials["coated"].base.type == "rgl"
    assert parse(scene_to_json(scene), str(tmp_path)) == scene
    obj["materials"] = {"r": {"type": "rgl", "file": "x.ptab"}}
    assert "not one of the file kinds read here (.bsdf)" in error(obj, str(tmp_path)).problem
    obj["materials"] = {"r": {"type": "rgl", "file": "x.bsdf", "sampling": "uniform"}}
    e = error(obj, str(tmp_path))
    assert e.where == "materials.r.sampling" and "'file', 'cosine'" in e.problem


def test_full_scene_fields(folder):
    scene = parse(FULL, folder)
    assert scene.path == os.path.join(folder, "scene.json")
    assert scene.materials["t"].file == os.path.join(folder, "a.ptab")
    assert scene.materials["paint"].base.file == os.path.join(folder, "base.ptab")
    assert scene.materials["paint"].base.two_sided is True  # the car paint's two_sided reaches its base
    assert scene.shapes[4].file == os.path.join(folder, "meshes", "m.obj")
    assert scene.environment.file == os.path.join(folder, "env", "studio.exr")
    assert scene.materials["l"].albedo == (0.25, 0.25, 0.25)
    assert scene.materials["c"].roughness == (0.1, 0.3) and scene.materials["c"].metal is None
    assert scene.camera.focus_distance == 4.5
    assert [s.type for s in scene.shapes] == ["sphere", "plane", "ball", "panel", "mesh", "sphere", "sphere"]
    assert [type(light).__name__ for light in scene.lights] == ["PointLight", "QuadLight"]
    assert np.allclose(scene.lights[1].normal, [0, 1, 0]) and scene.lights[1].area == pytest.approx(1.0)
    for s in scene.shapes:
        assert s.transform.dtype == np.float64 and not s.transform.flags.writeable


def test_relative_paths_from_the_scene_folder(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "env.hdr").write_bytes(b"")
    obj = {"version": 1, "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]},
           "environment": {"type": "map", "file": "../env.hdr"}}  # fmt: skip
    path = tmp_path / "sub" / "s.json"
    path.write_text(json.dumps(obj))
    cwd = os.getcwd()
    try:
        os.chdir("/")
        scene = load_scene(str(path))
    finally:
        os.chdir(cwd)
    assert scene.environment.file == str(tmp_path / "env.hdr")


def test_canonical_json_round_trips(folder):
    scene = parse(FULL, folder)
    canonical = json.loads(json.dumps(scene_to_json(scene)))
    assert parse_scene(canonical, scene.path) == scene
    assert canonical["materials"]["au"]["metal"] == "Au" and "eta" not in canonical["materials"]["au"]
    assert canonical["shapes"][1]["transform"]["matrix"][0] == [2, 0, 0, 0]
    changed = copy.deepcopy(canonical)
    changed["shapes"][1]["transform"]["matrix"][0][3] = 0.5
    assert parse_scene(changed, scene.path) != scene


# --- transforms and conventions --------------------------------------------------------------


def _transform(t, folder):
    obj = {"version": 1, "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]},
           "materials": {"m": {"type": "lambert"}},
           "shapes": [{"type": "sphere", "material": "m", "transform": t}]}  # fmt: skip
    return parse(obj, folder).shapes[0].transform


def test_transform_order_scale_rotate_translate(folder):
    m = _transform({"translate": [1, 2, 3], "rotate": [[0, 0, 1], 90], "scale": 2}, folder)
    # (1, 0, 0) scaled to (2, 0, 0), rotated about +z to (0, 2, 0), moved by (1, 2, 3)
    assert np.allclose(m @ [1, 0, 0, 1], [1, 4, 3, 1])
    # a rotation list applies first to last: x about +z by 90 gives +y, then about +x by 90 gives +z
    r = _transform({"rotate": [[[0, 0, 1], 90], [[1, 0, 0], 90]]}, folder)
    assert np.allclose(r @ [1, 0, 0, 0], [0, 0, 1, 0])
    # right-handed about +y: +z goes to +x
    assert np.allclose(_transform({"rotate": [[0, 2, 0], 90]}, folder) @ [0, 0, 1, 0], [1, 0, 0, 0])
    mat = [[0, -1, 0, 5], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    assert np.array_equal(_transform({"matrix": mat}, folder), mat)


def test_camera_rays(folder):
    scene = parse({"version": 1, "camera": {"position": [1, 2, 3], "look_at": [1, 2, -1], "fov": 60,
                                            "width": 200, "height": 100}}, folder)  # fmt: skip
    cam = scene.camera
    assert np.allclose(cam.ray_direction(100, 50), [0, 0, -1])
    top = cam.ray_direction(100, 0)  # the top edge is fov / 2 above the axis
    assert math.degrees(math.atan2(top[1], -top[2])) == pytest.approx(30)
    right = cam.ray_direction(200, 50)  # right is +x when looking down -z with y up
    assert math.atan2(right[0], -right[2]) == pytest.approx(math.atan(2 * math.tan(math.pi / 6)))


def test_environment_convention():
    env = MapEnvironment(file="x.exr", rotation=0.0, intensity=1.0)
    assert np.allclose(env.direction(0.0, 0.0), [0, 1, 0])
    assert np.allclose(env.direction(0.5, 0.5), [0, 0, 1])
    assert np.allclose(env.direction(0.25, 0.5), [1, 0, 0])
    assert np.allclose(env.direction(0.0, 0.5), [0, 0, -1])
    turned = MapEnvironment(file="x.exr", rotation=90.0, intensity=1.0)
    assert np.allclose(turned.direction(0.25, 0.5), [0, 0, -1])
    rng = np.random.default_rng(1)
    uv = np.column_stack([rng.uniform(0, 1, 50), rng.uniform(0.01, 0.99, 50)])
    for e in (env, turned, MapEnvironment(file="x.exr", rotation=-33.0, intensity=1.0)):
        assert np.allclose(e.uv(e.direction(uv[:, 0], uv[:, 1])), uv)


def test_overrides(folder):
    scene = parse(FULL, folder)
    s = with_overrides(scene, spp=8, integrator="direct", seed=9, width=10, height=20)
    assert (s.render.spp, s.render.integrator, s.render.seed) == (8, "direct", 9)
    assert (s.camera.width, s.camera.height) == (10, 20)
    assert s.render.max_depth == scene.render.max_depth and s.materials == scene.materials
    assert with_overrides(scene) == scene
    for kwargs, where in [({"spp": 0}, "--spp"), ({"integrator": "bdpt"}, "--integrator"), ({"seed": -1}, "--seed"),
                          ({"width": 10**6}, "--width"), ({"height": 2.5}, "--height")]:  # fmt: skip
        with pytest.raises(FormatError) as info:
            with_overrides(scene, **kwargs)
        assert info.value.where == where and info.value.path == "command line"


def test_cache_settings_defaults_and_overrides(folder):
    scene = parse(FULL, folder)
    c = scene.render.cache
    assert (c.resolution, c.error, c.guide, c.block) == (24, 0.5, 0.5, 8)
    overrides = {"cache_resolution": 16, "cache_error": 1.5, "cache_guide": 0.3, "cache_block": 2}
    s = with_overrides(scene, integrator="cache-guided", **overrides)
    assert s.render.integrator == "cache-guided"
    c = s.render.cache
    assert (c.resolution, c.error, c.guide, c.block) == (16, 1.5, 0.3, 2)
    obj = copy.deepcopy(FULL)
    obj["render"]["cache"] = {"resolution": 32, "block": 1}
    c = parse(obj, folder).render.cache
    assert (c.resolution, c.block) == (32, 1)
    assert scene.render.cache.hit_paths == 4 and with_overrides(scene, cache_hit_paths=2).render.cache.hit_paths == 2
    for kwargs, where in [({"cache_resolution": 200}, "--cache-resolution"), ({"cache_error": 5.0}, "--cache-error"),
                          ({"cache_guide": 0.0}, "--cache-guide"), ({"cache_block": 17}, "--cache-block"),
                          ({"cache_guide_bounces": 0}, "--cache-guide-bounces"),
                          ({"cache_block": 2.5}, "--cache-block"), ({"cache_hit_paths": 0}, "--cache-hit-paths"),
                          ({"cache_light_samples": 17}, "--cache-light-samples"),
                          ({"cache_train_passes": 9}, "--cache-train-passes"),
                          ({"cache_train_spp": 0}, "--cache-train-spp"),
                          ({"cache_train_guide": 0.99}, "--cache-train-guide"),
                          ({"cache_train_bounces": 17}, "--cache-train-bounces")]:  # fmt: skip
        with pytest.raises(FormatError) as info:
            with_overrides(scene, **kwargs)
        assert info.value.where == where and info.value.path == "command line"


# --- errors name the key path ----------------------------------------------------------------


def _set(obj, path, value):
    *head, last = path
    for k in head:
        obj = obj[k]
    if value is _DELETE:
        del obj[last]
    else:
        obj[last] = value


_DELETE = object()
ERRORS = [
    # (key path in FULL, new value, expected where, words in the problem)
    (("camera", "fvo"), 3, "camera.fvo", "did you mean 'fov'"),
    (("shapes", 0, "analytic"), 1, "shapes[0].analytic", "true or false"),
    (
        ("shapes", 0),
        {"type": "sphere", "material": "l", "analytic": True, "transform": {"scale": [2, 1, 1]}},
        "shapes[0].analytic",
        "not a similarity",
    ),
    (
        ("shapes", 0),
        {
            "type": "sphere",
            "material": "l",
            "analytic": True,
            "transform": {"matrix": [[-1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},
        },
        "shapes[0].analytic",
        "mirror",
    ),
    (("shapes", 1, "analytic"), True, "shapes[1].analytic", "unknown key"),
    (("camera", "fov"), 180, "camera.fov", "(0, 180)"),
    (("camera", "fov"), 0, "camera.fov", "(0, 180)"),
    (("camera", "fov"), "30", "camera.fov", "must be a number"),
    (("camera", "position"), _DELETE, "camera.position", "missing required key"),
    (("camera", "position", 1), float("nan"), "camera.position[1]", "finite"),
    (("camera", "look_at"), [0, 1, 5], "camera.look_at", "must differ"),
    (("camera", "up"), [0, 0, 0], "camera.up", "non-zero"),
    (("camera", "up"), [0, -0.5, -5], "camera.up", "parallel"),
    (("camera", "width"), 64.0, "camera.width", "integer"),
    (("camera", "height"), 0, "camera.height", "[1, 16384]"),
    (("camera", "type"), "fisheye", "camera.type", "expected one of"),
    (("camera", "aperture_radius"), -1, "camera.aperture_radius", "in [0, 1e+09]"),
    (("camera", "focus_distance"), 0, "camera.focus_distance", "in [1e-06, 1e+09]"),
    (("render", "spp"), 0, "render.spp", "[1, 1048576]"),
    (("render", "integrator"), "paht", "render.integrator", "did you mean 'path'"),
    (("render", "max_depth"), True, "render.max_depth", "integer"),
    (("render", "seed"), -1, "render.seed", "integer"),
    (("render", "cache"), {"resolution": 4}, "render.cache.resolution", "[8, 128]"),
    (("render", "cache"), {"resolution": 16.5}, "render.cache.resolution", "integer"),
    (("render", "cache"), {"error": 0}, "render.cache.error", "[0.01, 4]"),
    (("render", "cache"), {"guide": 1}, "render.cache.guide", "[0.05, 0.95]"),
    (("render", "cache"), {"guide_bounces": 17}, "render.cache.guide_bounces", "[1, 16]"),
    (("render", "cache"), {"block": 0}, "render.cache.block", "[1, 16]"),
    (("render", "cache"), {"hit_paths": 17}, "render.cache.hit_paths", "[1, 16]"),
    (("render", "cache"), {"light_samples": 0}, "render.cache.light_samples", "[1, 16]"),
    (("render", "cache"), {"train_passes": 9}, "render.cache.train_passes", "[0, 8]"),
    (("render", "cache"), {"train_spp": 0}, "render.cache.train_spp", "[1, 16]"),
    (("render", "cache"), {"train_guide": 0.01}, "render.cache.train_guide", "[0.05, 0.95]"),
    (("render", "cache"), {"train_bounces": 0}, "render.cache.train_bounces", "[1, 16]"),
    (("render", "cache"), {"eror": 1}, "render.cache.eror", "did you mean 'error'"),
    (("render", "cache"), 3, "render.cache", "object"),
    (("materials", "paint", "coat", "eta"), 0.5, "materials.paint.coat.eta", "in [1, 1000]"),
    (("materials", "paint", "coat", "roughnes"), 0.1, "materials.paint.coat.roughnes", "did you mean 'roughness'"),
    (("materials", "paint", "base"), {"type": "dielectric"}, "materials.paint.base.type", "expected one of"),
    (("materials", "paint", "base", "two_sided"), True, "materials.paint.base.two_sided", "carpaint"),
    (("materials", "paint", "base", "file"), "missing.ptab", "materials.paint.base.file", "no such file"),
    (("materials", "t", "file"), "a.png", "materials.t.file", "file kinds"),
    (("materials", "t", "file"), "folder.ptab", "materials.t.file", "not a regular file"),
    (("materials", "f", "file"), "nofit.json", "materials.f.file", "no such file"),
    (("materials", "t", "tint"), [1, -1, 1], "materials.t.tint[1]", ">= 0"),
    (("materials", "t", "tint"), [1, 1], "materials.t.tint", "array of 3"),
    (("materials", "t", "tint"), "red", "materials.t.tint", "[r, g, b]"),
    (("materials", "t", "two_sided"), 1, "materials.t.two_sided", "true or false"),
    (("materials", "l", "albedo"), 1.5, "materials.l.albedo", "[0, 1]"),
    (("materials", "d", "eta"), 0.9, "materials.d.eta", "in [1, 1000]"),
    (("materials", "d", "roughness"), 1.5, "materials.d.roughness", "[0, 1]"),
    (("materials", "d", "two_sided"), True, "materials.d.two_sided", "unknown key"),
    (("materials", "c", "roughness"), [0.1, -0.1], "materials.c.roughness[1]", "[0, 1]"),
    (("materials", "c", "k"), _DELETE, "materials.c.k", "missing required key"),
    (("materials", "c", "eta"), [0, 1, 1], "materials.c.eta[0]", "in (0, 1000]"),
    (("materials", "au", "metal"), "Gold", "materials.au.metal", "expected one of"),
    (("materials", "au", "eta"), 1.0, "materials.au.eta", "not both"),
    (("materials", "bad name"), {"type": "lambert"}, "materials.bad name", "material name"),
    (("materials", "x"), {"albedo": 1}, "materials.x.type", "missing required key"),
    (("shapes", 2, "material"), "pain", "shapes[2].material", "undefined material"),
    (("shapes", 2, "transform", "rotate"), [[0, 0, 0], 10], "shapes[2].transform.rotate[0]", "non-zero"),
    (("shapes", 2, "transform", "rotate"), [[0, 1], 10], "shapes[2].transform.rotate[0]", "array of 3"),
    (("shapes", 3, "transform", "rotate", 1, 1), "ten", "shapes[3].transform.rotate[1][1]", "number"),
    (("shapes", 1, "transform", "scale"), [1, 0, 1], "shapes[1].transform.scale", "non-zero"),
    (("shapes", 1, "transform", "translate"), [1, 2, 3], "shapes[1].transform", ""),  # valid: no error expected
    (("shapes", 4, "transform", "scale"), 2, "shapes[4].transform.scale", "unknown key"),
    (("shapes", 4, "transform", "matrix", 3), [0, 0, 1, 1], "shapes[4].transform.matrix[3]", "[0, 0, 0, 1]"),
    (("shapes", 4, "transform", "matrix", 2), [0, 0, 0, 0], "shapes[4].transform", "singular"),
    (("shapes", 1, "transform", "scale"), 1e-200, "shapes[1].transform.scale", "1e-06 to 1e+09 in size"),
    (("shapes", 4, "transform", "matrix", 2), [0, 0, 1e-200, 0], "shapes[4].transform", "singular"),
    (("shapes", 1, "transform", "scale"), 1e300, "shapes[1].transform.scale", "32-bit float range"),
    (("shapes", 0, "radius"), -1, "shapes[0].radius", "in [1e-06, 1e+09]"),
    (("shapes", 0, "radius"), 10**400, "shapes[0].radius", "too large"),
    (("shapes", 0, "size"), [1, 1], "shapes[0].size", "known keys: type, material, transform, radius"),
    (("shapes", 1, "size"), [1, 0], "shapes[1].size[1]", "in [1e-06, 1e+09]"),
    (("shapes", 4, "file"), "nope.obj", "shapes[4].file", "no such file"),
    (("shapes", 4, "file"), "a.ptab", "shapes[4].file", "file kinds"),
    (("shapes", 5), "sphere", "shapes[5]", "object"),
    (("shapes",), {"type": "sphere"}, "shapes", "array"),
    (("lights", 0, "intensity"), [-1, 1, 1], "lights[0].intensity[0]", ">= 0"),
    (("lights", 0, "radiance"), 1, "lights[0].radiance", "unknown key"),
    (("lights", 1, "v"), [1, 0, 0], "lights[1].v", "parallel"),
    (("lights", 1, "u"), [0, 0, 0], "lights[1].u", "non-zero"),
    (("lights", 1, "type"), "laser", "lights[1].type", "expected one of 'point', 'quad', 'spot'"),
    (("environment", "file"), "env/studio.png", "environment.file", "file kinds"),
    (("environment", "file"), "env/other.exr", "environment.file", "no such file"),
    (("environment", "intensity"), -1, "environment.intensity", "in [0, 1e+15]"),
    (("environment", "radiance"), 1, "environment.radiance", "unknown key"),
    (("environment",), {"type": "constant"}, "environment.radiance", "missing required key"),
    (("version",), 2, "version", "unsupported"),
    (("version",), _DELETE, "version", "missing required key"),
    (("camrea",), {}, "camrea", "did you mean 'camera'"),
]


@pytest.mark.parametrize(("path", "value", "where", "words"), ERRORS, ids=[e[2] for e in ERRORS])
def test_error_key_paths(path, value, where, words, folder):
    obj = copy.deepcopy(FULL)
    _set(obj, path, value)
    if not words:
        parse(obj, folder)
        return
    e = error(obj, folder)
    assert e.where == where, str(e)
    assert words in e.problem
    assert e.path == os.path.join(folder, "scene.json")


def test_not_an_object(folder):
    assert error([1, 2], folder).where == ""
    assert "JSON object" in error("scene", folder).problem


def test_a_bsdf_xml_side_is_named_as_on_the_command_line(tmp_path):
    """`window.xml#back` in a scene, as `patina info window.xml#back`: the side stays on the
    path the renderer loads; a missing document is named without it."""
    shutil.copy(os.path.join(ROOT, "materials", "radiance", "klems_aniso_high.xml"), tmp_path / "shade.xml")

    def scene(file: str) -> dict:
        return {"version": 1, "camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]},
                "materials": {"shade": {"type": "table", "file": file}}}  # fmt: skip

    back = parse_scene(scene("shade.xml#back"), tmp_path / "s.json")
    assert back.materials["shade"].file == f"{tmp_path / 'shade.xml'}#back"
    for file, words in (("gone.xml#back", "no such file"), ("shade.xml#side", "expected #front or #back")):
        with pytest.raises(FormatError, match=words) as info:
            parse_scene(scene(file), tmp_path / "s.json")
        assert info.value.where == "materials.shade.file"


def test_file_errors(tmp_path):
    cases = {
        b'{"version": 1,\n  "camera": {"position": [0, 0, 1] "look_at": [0, 0]}}': ("line 2, column 36", "JSON syntax"),
        b"\xef\xbb\xbf\x00\xff": ("byte 1", "UTF-8"),
        b"[" * 100_000: ("", "nested too deeply"),
        b'{"version": 1, "version": 1}': ("version", "more than once"),
        b'{"version": ' + b"9" * 5000 + b"}": ("", "not readable"),
        b"": ("line 1, column 1", "JSON syntax"),
    }
    for i, (data, (where, words)) in enumerate(cases.items()):
        path = tmp_path / f"s{i}.json"
        path.write_bytes(data)
        with pytest.raises(FormatError) as info:
            load_scene(path)
        assert (info.value.where, info.value.path) == (where, str(path)), str(info.value)
        assert words in info.value.problem
    with pytest.raises(FormatError, match="cannot open"):
        load_scene(tmp_path / "missing.json")
    with pytest.raises(FormatError, match="directory"):
        load_scene(tmp_path)


# --- the bundled scenes -----------------------------------------------------------------------


def test_bundled_scenes_parse(tmp_path):
    """Each bundled scene parses, with empty stand-ins for data files other work provides."""
    names = sorted(glob.glob(os.path.join(ROOT, "materials", "scenes", "*.json")))
    assert {os.path.basename(n) for n in names} >= {
        "preview-ball.json", "diffuse-sphere.json", "conductor-sphere.json", "area-box.json", "lambert-plane-point.json"
    }  # fmt: skip
    copy_dir = tmp_path / "materials" / "scenes"
    copy_dir.mkdir(parents=True)
    for name in names:
        target = copy_dir / os.path.basename(name)
        shutil.copy(name, target)
        obj = json.loads(target.read_text())
        write_stand_ins(obj, str(copy_dir))
        scene = load_scene(target)
        assert scene.shapes and scene.camera.width * scene.camera.height <= 1 << 20
        assert parse_scene(json.loads(json.dumps(scene_to_json(scene))), scene.path) == scene


# --- property tests: nothing but FormatError -----------------------------------------------------

KEYS = ["type", "file", "radius", "size", "transform", "rotate", "matrix", "scale", "eta", "k", "metal", "base",
        "coat", "roughness", "two_sided", "position", "look_at", "up", "fov", "material", "version", "x"]  # fmt: skip
SCALARS = (
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**20), max_value=10**20)
    | st.sampled_from([0, -1, 1, 2, 10**400, -0.0, 1e-320, 1e308, "", ".", "a.ptab", "Au", "sphere", "map"])
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=8)
)
JSON_VALUES = st.recursive(
    SCALARS,
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.sampled_from(KEYS) | st.text(max_size=5), inner, max_size=4)
    ),
    max_leaves=12,
)


def _mutate(data, obj):
    """One random change somewhere in the tree: replace a value, delete or add a key, or drop an element."""
    node = obj
    while True:
        children = list(node.items()) if isinstance(node, dict) else list(enumerate(node))
        if not children:
            break
        key, child = data.draw(st.sampled_from(children))
        if isinstance(child, (dict, list)) and child and data.draw(st.booleans()):
            node = child
            continue
        action = data.draw(st.sampled_from(["replace", "delete", "add"]))
        if action == "replace":
            node[key] = data.draw(JSON_VALUES)
        elif action == "delete":
            del node[key]
        elif isinstance(node, dict):
            node[data.draw(st.sampled_from(KEYS))] = data.draw(JSON_VALUES)
        else:
            node.append(data.draw(JSON_VALUES))
        return


PROPERTY = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@PROPERTY
@given(data=st.data())
def test_mutated_scene_is_scene_or_format_error(data, folder):
    obj = copy.deepcopy(FULL)
    for _ in range(data.draw(st.integers(1, 3))):
        _mutate(data, obj)
    try:
        scene = parse(obj, folder)
    except FormatError as e:
        assert e.problem
        return
    assert parse_scene(json.loads(json.dumps(scene_to_json(scene))), scene.path) == scene


@PROPERTY
@given(
    edits=st.lists(st.tuples(st.integers(0, 4000), st.binary(max_size=4), st.integers(0, 3)), min_size=1, max_size=4),
    cut=st.integers(0, 5000),
)
def test_damaged_scene_bytes_give_format_error(edits, cut, folder):
    data = bytearray(json.dumps(FULL).encode())
    for position, insert, remove in edits:
        at = min(position, len(data))
        data[at : at + remove] = insert
    path = os.path.join(folder, "damaged.json")
    with open(path, "wb") as f:
        f.write(bytes(data[: max(cut, len(data) // 2)]))
    try:
        load_scene(path)
    except FormatError as e:
        assert e.path == path
