"""The renderer against analytic answers: a white furnace, a Lambert plane under a point
light and under a quad light, a diffuse sphere under an environment map integrated by
brute force; widths 1, 4 and 8 give the same bits; seeds and thread counts are
deterministic; a cancelled render is valid; no NaN or Inf anywhere."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from conftest import WIDTHS
from patina.render.run import PreparedScene, render
from patina.scene.reading import parse_scene
from quad_light import quad_light_floor, quad_light_scene
from repo_paths import ROOT


def scene_of(obj: dict, folder: str = ROOT):
    return parse_scene(obj, os.path.join(folder, "test.json"))


def furnace(material: dict, spp: int = 64, depth: int = 64, size: int = 32) -> dict:
    return {
        "version": 1,
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 35, "width": size, "height": size},
        "render": {"spp": spp, "integrator": "path", "max_depth": depth, "seed": 3},
        "materials": {"m": material},
        "shapes": [{"type": "sphere", "radius": 1, "material": "m"}],
        "environment": {"type": "constant", "radiance": 1.0},
    }


@pytest.mark.parametrize("eta", [1.5, 1.0001])
def test_a_smooth_glass_sphere_in_the_furnace_shows_the_furnace(eta):
    # radiance is conserved through a closed, lossless dielectric (entering and leaving, the
    # eta^2 factors cancel); index-matched glass is the ill-conditioned generalized half vector
    r = render(scene_of(furnace({"type": "dielectric", "roughness": 0.0, "eta": eta}, spp=128)))
    values = r.rgb[np.isfinite(r.depth)]
    assert abs(values.mean() - 1.0) < 4 * values.std() / math.sqrt(values.size) + 1e-3


def test_white_furnace_lambert_albedo_one_renders_one():
    r = render(scene_of(furnace({"type": "lambert", "albedo": 1.0}, spp=128)))
    hit = np.isfinite(r.depth)
    assert hit.sum() > 200
    # every pixel is an unbiased estimate of 1; the image mean within 4 standard errors
    values = r.rgb[hit]
    assert abs(values.mean() - 1.0) < 4 * values.std() / math.sqrt(values.size) + 1e-3
    assert np.allclose(r.rgb[~hit], 1.0)  # the environment seen directly


@pytest.mark.parametrize(
    "material",
    [
        {"type": "conductor", "roughness": 0.3, "eta": 1.0, "k": 1e3},  # F ~ 1 (the largest k): a white GGX lobe
        {"type": "conductor", "roughness": 0.05, "metal": "Au"},
        {"type": "carpaint", "base": {"type": "lambert", "albedo": 0.9}, "coat": {"eta": 1.5, "roughness": 0.0}},
        {"type": "dielectric", "roughness": 0.3, "eta": 1.5},  # single scattering loses energy, never gains
    ],
)
def test_energy_conserving_materials_stay_at_or_below_one_in_the_furnace(material):
    r = render(scene_of(furnace(material, spp=64)))
    hit = np.isfinite(r.depth)
    values = r.rgb[hit]
    assert np.isfinite(values).all()
    assert values.mean() <= 1.0 + 4 * values.std() / math.sqrt(values.size) + 1e-3
    assert values.mean() > 0.3


def test_lambert_plane_under_a_point_light_matches_the_analytic_irradiance():
    scene = scene_of(
        {
            "version": 1,
            "camera": {"position": [0, 4, 4], "look_at": [0, 0, 0], "fov": 40, "width": 64, "height": 48},
            "render": {"spp": 64, "integrator": "direct", "seed": 0},
            "materials": {"grey": {"type": "lambert", "albedo": [0.5, 0.25, 0.8]}},
            "shapes": [{"type": "plane", "material": "grey", "size": [10, 10]}],
            "lights": [{"type": "point", "position": [0.5, 2, -0.5], "intensity": [10, 20, 5]}],
        }
    )
    r = render(scene)
    cam = scene.camera

    def on_plane(sub: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """cos / d^2 and the hit point averaged over sub x sub points of each pixel (a box filter)."""
        ys, xs = np.mgrid[0 : cam.height * sub, 0 : cam.width * sub] + 0.5
        d = cam.ray_direction(xs / sub, ys / sub)
        p = np.asarray(cam.position) + (-cam.position[1] / d[..., 1])[..., None] * d
        to_light = np.array([0.5, 2, -0.5]) - p
        dist2 = (to_light**2).sum(-1)
        g = to_light[..., 1] / np.sqrt(dist2) / dist2
        box = lambda a: a.reshape(cam.height, sub, cam.width, sub, *a.shape[2:]).mean(axis=(1, 3))  # noqa: E731
        return box(g), box(p), d

    g, p, _ = on_plane(8)
    expected = np.array([0.5, 0.25, 0.8]) / math.pi * np.array([10, 20, 5]) * g[..., None]
    inside = (np.abs(p[..., 0]) < 4.9) & (np.abs(p[..., 2]) < 4.9)
    # 64 jittered samples against the 8 x 8 box average of the exact field
    rel = np.abs(r.rgb[inside] - expected[inside]) / expected[inside]
    assert np.median(rel) < 2e-3
    assert rel.max() < 0.02
    # illuminance AOV: E = I cos / d^2 in lux (683 lm/W x luminance of the RGB intensity)
    lux = 683 * (0.2126 * 10 + 0.7152 * 20 + 0.0722 * 5) * g
    assert np.median(np.abs(r.illuminance[inside] - lux[inside]) / lux[inside]) < 2e-3


def test_lambert_plane_under_a_quad_light_matches_the_form_factor():
    scene = scene_of(quad_light_scene(48, 256))
    r = render(scene)
    expected, under = quad_light_floor(scene.camera, 6)
    seen = np.isfinite(r.depth) & (r.depth > 4.5)  # the floor (the light's dark back is 4 m away)
    floor = seen & ~under  # not under the light's outline, seen from the camera
    got = r.rgb[..., 0][floor]
    assert abs(got.mean() / expected[floor].mean() - 1) < 0.01
    assert np.median(np.abs(got - expected[floor]) / expected[floor]) < 0.05


def test_environment_importance_sampling_matches_brute_force_integration(tmp_path):
    from patina.render.envmap import solid_angles
    from patina.render.images import write_exr

    # a small map with a bright patch (importance sampling matters) and a coloured sky
    h, w = 32, 64
    env = np.full((h, w, 3), 0.2, np.float32)
    env[: h // 2] *= np.array([0.6, 0.8, 1.4], np.float32)
    env[6:9, 20:24] = [40.0, 30.0, 20.0]
    write_exr(str(tmp_path / "env.exr"), {"beauty": env}, {})
    scene = scene_of(
        {
            "version": 1,
            "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 35, "width": 40, "height": 40},
            "render": {"spp": 256, "integrator": "direct", "seed": 2},
            "materials": {"m": {"type": "lambert", "albedo": 0.8}},
            "shapes": [{"type": "sphere", "radius": 1, "material": "m"}],
            "environment": {"type": "map", "file": "env.exr", "rotation": 30, "intensity": 1.5},
        },
        str(tmp_path),
    )
    r = render(scene)
    # pixels wholly on the sphere (at the silhouette some samples see the sky)
    hit = np.isfinite(r.depth)
    hit[1:-1, 1:-1] &= hit[:-2, 1:-1] & hit[2:, 1:-1] & hit[1:-1, :-2] & hit[1:-1, 2:]
    vv, uu = np.mgrid[0:h, 0:w] + 0.5
    dirs = scene.environment.direction(uu / w, vv / h).reshape(-1, 3)
    weights = (1.5 * env.reshape(-1, 3)) * solid_angles(h, w).reshape(-1, 1)
    n = r.normal[hit].astype(np.float64)
    # brute force over every env pixel (the map is piecewise constant; the renderer filters it
    # bilinearly, which only blurs what each pixel sees a little)
    irradiance = np.maximum(n @ dirs.T, 0) @ weights
    expected = 0.8 / math.pi * irradiance
    got = r.rgb[hit]
    assert abs(got.mean() / expected.mean() - 1) < 0.02
    assert np.median(np.abs(got - expected) / expected) < 0.06


def small_preview(spp: int = 4) -> dict:
    return {
        "version": 1,
        "camera": {"position": [0, 1.7, 5.6], "look_at": [0, 0.95, 0], "fov": 30, "width": 24, "height": 18},
        "render": {"spp": spp, "integrator": "path", "max_depth": 5, "seed": 7},
        "materials": {
            "paint": {
                "type": "carpaint",
                "base": {"type": "table", "file": "materials/red-plastic-iso.ptab"},
                "coat": {"eta": 1.5, "roughness": 0.0},
            },
            "gold": {"type": "conductor", "roughness": [0.1, 0.3], "metal": "Au"},
            "glass": {"type": "dielectric", "roughness": 0.1, "eta": 1.5},
            "floor": {"type": "lambert", "albedo": 0.5},
        },
        "shapes": [
            {"type": "ball", "material": "paint"},
            {"type": "sphere", "radius": 0.4, "material": "gold", "transform": {"translate": [1.5, 0.4, 0]}},
            {"type": "sphere", "radius": 0.4, "material": "glass", "transform": {"translate": [-1.5, 0.4, 0]}},
            {"type": "plane", "material": "floor", "size": [20, 20]},
        ],
        "lights": [{"type": "quad", "center": [0, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5], "radiance": 5}],
        "environment": {"type": "constant", "radiance": [0.3, 0.4, 0.5]},
    }


def test_widths_render_the_same_bits():
    scene = scene_of(small_preview())
    prepared = PreparedScene(scene)
    images = [render(scene, simd=w, prepared=prepared).rgb for w in WIDTHS]
    assert np.isfinite(images[0]).all() and images[0].max() > 0
    assert all(np.array_equal(images[0], image) for image in images[1:])


def test_a_seed_and_any_thread_count_give_the_same_image_another_seed_does_not():
    scene = scene_of(small_preview())
    prepared = PreparedScene(scene)
    one = render(scene, threads=1, prepared=prepared).rgb
    two = render(scene, threads=2, prepared=prepared).rgb
    assert np.array_equal(one, two)
    other = scene_of({**small_preview(), "render": {"spp": 4, "integrator": "path", "max_depth": 5, "seed": 8}})
    assert not np.array_equal(one, render(other, prepared=PreparedScene(other)).rgb)


def test_a_cancelled_render_keeps_its_first_pass_and_a_second_cancel_stops_at_once():
    from patina.native import _core

    scene = scene_of(small_preview(spp=64))
    prepared = PreparedScene(scene)
    tiles = math.ceil(scene.camera.width / 16) * math.ceil(scene.camera.height / 16)
    # cancelled before it starts: one cancel still lets the first pass finish, so no pixel is
    # left without a sample (it used to leave every pixel at 0)
    job = _core.RenderJob(prepared.core, _core.RenderOptions(spp=64, max_depth=5, seed=0, threads=1, passes=8))
    job.cancel()
    job.start()
    job.wait()
    images = job.resolve()
    p = job.progress()
    assert not p.finished and p.cancelled and p.items_done == tiles
    assert np.isfinite(images.rgb).all()
    assert set(np.unique(images.samples)) == {8.0}  # every pixel: the whole first pass of 8
    # a second cancel stops at the items in flight: here none has started
    job = _core.RenderJob(prepared.core, _core.RenderOptions(spp=64, max_depth=5, seed=0, threads=1, passes=8))
    job.cancel()
    job.cancel()
    job.start()
    job.wait()
    assert job.progress().items_done == 0


def test_a_render_cancelled_later_keeps_whole_passes_per_tile():
    from patina.native import _core

    scene = scene_of(small_preview(spp=64))
    prepared = PreparedScene(scene)
    job = _core.RenderJob(prepared.core, _core.RenderOptions(spp=64, max_depth=5, seed=0, threads=1, passes=8))
    job.start()
    while job.progress().items_done < 2 * math.ceil(scene.camera.width / 16) * math.ceil(scene.camera.height / 16):
        pass
    job.cancel()
    job.wait()
    samples = job.resolve().samples
    # every pixel is the mean of the samples it got: whole passes of 8, at least the first two
    assert set(np.unique(samples)) <= {16.0, 24.0, 32.0, 40.0, 48.0, 56.0, 64.0}


@pytest.mark.parametrize("name", sorted(os.listdir(os.path.join(ROOT, "materials", "scenes"))))
def test_bundled_scenes_render_without_nan_or_inf(name):
    if not name.endswith(".json"):
        return
    from patina.scene.reading import load_scene, with_overrides

    scene = with_overrides(load_scene(os.path.join(ROOT, "materials", "scenes", name)), spp=2, width=32, height=24)
    r = render(scene)
    for image in (r.rgb, r.albedo, r.normal, r.illuminance):
        assert np.isfinite(image).all()
    assert r.rgb.max() > 0


def test_job_settings_take_the_scene_files_max_depth_as_it_is():
    from patina.native import _core
    from patina.render.run import job_settings
    from patina.scene.reading import with_overrides

    scene = scene_of(small_preview(spp=4))
    options = job_settings(scene)
    assert options.max_depth == scene.render.max_depth and options.integrator == "path"
    assert options.cache == _core.CacheSettings()
    direct = job_settings(with_overrides(scene, integrator="direct"))
    assert direct.max_depth == 2 and direct.integrator == "path"  # direct light: two segments
    cached = job_settings(with_overrides(scene, integrator="cache-guided", cache_train_bounces=3))
    assert cached.integrator == "cache-guided" and cached.cache.train_bounces == 3


def test_render_options_are_named_checked_in_one_place_and_travel_whole():
    import pickle

    from patina.native import _core
    from patina.scene.reading import MAX_DEPTH, MAX_SPP

    options = _core.RenderOptions(spp=8, max_depth=5, aa="adaptive", sampler="independent")
    options.cache.train_bounces = 4
    again = pickle.loads(pickle.dumps(options))
    assert again == options and again.cache.train_bounces == 4 and again.aa == "adaptive"
    with pytest.raises(TypeError, match="no field 'depth'"):
        _core.RenderOptions(depth=3)
    with pytest.raises(ValueError, match="integrator: 'bidir' is not one of 'path', 'cache', 'cache-guided'"):
        _core.RenderOptions(integrator="bidir")
    for field, value, message in [
        ("spp", 0, "spp: must be an integer from 1 to 1048576, got 0"),
        ("max_depth", 1025, "max_depth: must be an integer from 1 to 1024, got 1025"),
        ("aa_threshold", 1.5, r"aa_threshold: must be a number in \[0, 1\], got 1.5"),
    ]:
        with pytest.raises(ValueError, match=message):
            _core.RenderOptions(**{field: value}).check()
    # the scene reader's limits are the renderer's table
    ranges = {key: (lo, hi) for key, _integer, lo, hi in _core.render_option_ranges()}
    assert ranges["spp"][1] == MAX_SPP and ranges["max_depth"][1] == MAX_DEPTH


def test_a_jobs_results_are_typed():
    from patina.native import _core

    prepared = PreparedScene(scene_of(small_preview(spp=2)))
    job = _core.RenderJob(prepared.core, _core.RenderOptions(spp=2, max_depth=3, threads=1))
    job.start()
    job.wait()
    p, images, times = job.progress(), job.resolve(), job.stage_times()
    assert p.finished and p.items_done == p.items_total and p.cache_points == 0
    assert images.rgb.shape[2] == 3 and images.aa_level is None and (images.samples == 2).all()
    assert times.camera_rays == p.samples_done and "trace_camera" in times.stages
