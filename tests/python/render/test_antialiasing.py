"""The adaptive antialiasing (docs/antialiasing.md) on real scenes: a flat noisy region stays
at level 1, edges are refined where they are, a 90-degree turn of the camera turns the
image, widths 1/4/8 and thread counts give the same bits, no NaN/Inf; the API, the scene
keys, the CLI options and the EXR header; bad values exit 2 with one line."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from patina.bundled import materials_path
from patina.cli import main
from patina.native import _core
from patina.render.images import read_exr_layers
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, parse_scene, with_overrides
from repo_paths import ROOT

SIZE = 32
TAN = math.tan(math.radians(20.0))  # fov 40


def scene_of(obj: dict):
    return parse_scene(obj, os.path.join(ROOT, "test.json"))


def top_down(shapes: list, up=(0, 0, -1), spp: int = 1, integrator: str = "direct", **render_keys) -> dict:
    """A camera 4 m above the plane y = 0 looking down: image x is world x, image y world z
    (up = -z), at 4 TAN metres from the centre to an edge of the image."""
    return {
        "version": 1,
        "camera": {
            "position": [0, 4, 0],
            "look_at": [0, 0, 0],
            "up": list(up),
            "fov": 40,
            "width": SIZE,
            "height": SIZE,
        },
        "render": {"spp": spp, "integrator": integrator, "seed": 5, **render_keys},
        "materials": {"grey": {"type": "lambert", "albedo": 0.6}},
        "shapes": shapes,
        "lights": [{"type": "point", "position": [0.7, 3, 0.4], "intensity": 20}],
    }


def world_x(fx: float) -> float:
    """Where film column position fx meets the plane y = 0."""
    return 4 * TAN * (2 * fx / SIZE - 1)


def half_plane_left_of(fx: float) -> dict:
    """A plane covering the image left of film position fx (nothing to its right)."""
    edge = world_x(fx)
    return {
        "type": "plane",
        "material": "grey",
        "size": [edge + 10, 20],
        "transform": {"translate": [(edge - 10) / 2, 0, 0]},
    }


def test_the_pattern_data_is_what_the_docs_say():
    p = _core.aa_pattern()
    pos = np.asarray(p["positions"])
    assert pos.shape == (28, 2)
    assert np.allclose(pos[:4], [[0, 0], [1, 0], [0, 1], [1, 1]])
    assert np.allclose(pos[4:8], [[0.2, 0.5], [0.4, 0.5], [0.6, 0.5], [0.8, 0.5]])
    assert np.allclose(np.asarray(p["weights"]).sum(axis=1), 1.0, atol=1e-6)
    # without level 2: E..H weigh nothing, a run of zones' weights sum to 1, other subsets are unused (0)
    direct = np.asarray(p["direct_weights"])
    runs = [z for z in range(32) if z and ((z + (z & -z)) & z) == 0]
    assert np.all(direct[:, 4:8] == 0)
    assert np.allclose(direct[runs].sum(axis=1), 1.0, atol=1e-6)
    assert np.all(np.delete(direct, runs, axis=0) == 0)
    assert p["default_threshold"] == pytest.approx(0.15)


def test_a_flat_noisy_region_stays_at_level_one():
    # a plane under an environment, path traced at 1 spp: every pixel's radiance is noisy,
    # the signal (hit, depth, normal, albedo x the fixed light samples) is flat
    obj = top_down([{"type": "plane", "material": "grey", "size": [40, 40]}], integrator="path")
    obj["lights"] = []
    obj["environment"] = {"type": "constant", "radiance": 1.0}
    scene = scene_of(obj)
    r = render(scene, aa="adaptive")
    assert r.aa_level is not None and r.aa_rays is not None
    assert np.mean(r.aa_level > 1) <= 0.01
    assert r.rgb.std() > 0.02  # it is noisy
    assert np.isfinite(r.rgb).all()
    # the mean of corners is an unbiased estimate like the uniform sampler's (the image of
    # radiance 0.6 x 1 everywhere)
    u = render(scene, aa="uniform")
    assert abs(r.rgb.mean() - u.rgb.mean()) < 4 * r.rgb.std() / SIZE + 0.01
    assert r.camera_rays / (SIZE * SIZE) < 1.2  # the corners and their tile borders


def test_a_scene_without_discontinuities_is_the_mean_of_its_corners():
    # a plane under one point light, direct light: noise-free, smooth; every pixel level 1
    # and, the radiance being smooth, within a hair of the pixel-centre value of a dense render
    scene = scene_of(top_down([{"type": "plane", "material": "grey", "size": [40, 40]}]))
    r = render(scene, aa="adaptive")
    assert (r.aa_level == 1).all() and (r.aa_rays == 1).all()
    dense = render(
        scene_of(
            {
                **top_down([{"type": "plane", "material": "grey", "size": [40, 40]}]),
                "render": {"spp": 64, "integrator": "direct", "seed": 1},
            }
        )
    )
    assert np.allclose(r.rgb, dense.rgb, rtol=0.02)


def test_a_vertical_edge_is_refined_in_its_column_only():
    scene = scene_of(top_down([half_plane_left_of(13.3)]))
    r = render(scene, aa="adaptive")
    refined = r.aa_level > 1
    assert refined[:, 13].all()
    assert not np.delete(refined, 13, axis=1).any()
    # the column is 30 % covered; the albedo AOV is the plane's albedo times the coverage
    assert np.allclose(r.albedo[:, 13, 0] / 0.6, 0.3, atol=0.05)


def test_a_horizontal_edge_is_refined_in_its_row_only():
    # the same plane seen with the camera turned: its edge runs along image rows
    scene = scene_of(top_down([half_plane_left_of(13.3)], up=(1, 0, 0)))
    r = render(scene, aa="adaptive")
    refined = r.aa_level > 1
    rows = np.flatnonzero(refined.any(axis=1))
    assert len(rows) == 1 and refined[rows[0]].all()
    # rows from the top: image y runs along world -x, so the plane (world x < its edge)
    # covers film y > 32 - 13.3 = 18.7, 30 % of row 18
    assert rows[0] == 18
    assert np.allclose(r.albedo[18, :, 0] / 0.6, 0.3, atol=0.05)


def test_under_one_point_light_the_sample_is_the_signal():
    # direct light from one point light through a pinhole: the integrator's sample is the
    # same for any random numbers, so it decides the refinement and nothing is traced twice
    # (a camera ray, a shadow ray and a BRDF-sampled ray at most a position)
    r = render(scene_of(top_down([half_plane_left_of(13.3)])), aa="adaptive")
    assert r.camera_rays > 32 * 32 and r.rays <= 3 * r.camera_rays


def test_where_the_sample_is_the_signal_the_paths_numbers_change_nothing():
    # the render job then draws the paths' numbers independently, not from Sobol (cheaper):
    # right only while any numbers give the same image. A second pass draws other numbers at
    # the same positions, so two passes must give the very bits of one (on a scene with a
    # shadow, a glossy lobe and patterns refined to level 3)
    shapes = [
        half_plane_left_of(13.3),
        {"type": "sphere", "material": "gold", "radius": 0.3, "transform": {"translate": [0.4, 0.5, 0.2]}},
    ]
    obj = top_down(shapes)
    obj["materials"]["gold"] = {"type": "conductor", "metal": "Au", "roughness": 0.2}
    one, two = (render(scene_of({**obj, "render": {**obj["render"], "spp": n}}), aa="adaptive") for n in (1, 2))
    assert np.array_equal(one.rgb, two.rgb) and (one.aa_level == 3).any()


def test_a_line_thinner_than_the_gaps_between_the_rays_is_found_by_the_geometric_pre_pass():
    # a dark strip 0.15 pixel wide down the middle of column 10 (film x 10.425 .. 10.575, between
    # the corners and between F and G): no ray of levels 1 and 2 sees it, its edges do
    lo, hi = world_x(10.425), world_x(10.575)
    obj = top_down(
        [
            {"type": "plane", "material": "grey", "size": [40, 40]},
            {
                "type": "plane",
                "material": "dark",
                "size": [hi - lo, 40],
                "transform": {"translate": [(lo + hi) / 2, 0.001, 0]},
            },
        ]
    )
    obj["materials"]["dark"] = {"type": "lambert", "albedo": 0.02}
    r = render(scene_of(obj), aa="adaptive")
    refined = r.aa_level > 1
    assert refined[:, 10].all() and not refined[:, :9].any() and not refined[:, 12:].any()
    # the strip darkens its column by about its coverage (to the zigzag's 4 % steps)
    loss = 1 - r.albedo[:, 10, 0] / 0.6
    assert np.all((loss > 0.05) & (loss < 0.3)), loss


def disc_scene(up) -> dict:
    # a sphere and its shadow on a plane, lit from the side: silhouettes and shadow edges
    # at every angle
    return top_down(
        [
            {"type": "plane", "material": "grey", "size": [40, 40]},
            {"type": "sphere", "material": "grey", "radius": 0.45, "transform": {"translate": [0.1, 0.5, -0.2]}},
        ],
        up=up,
    )


def test_a_scene_turned_by_90_degrees_gives_the_image_turned():
    a = render(scene_of(disc_scene((0, 0, -1))), aa="adaptive")
    b = render(scene_of(disc_scene((1, 0, 0))), aa="adaptive")
    # up -z -> up +x: the image turns by 90 degrees (np.rot90's sense, counter-clockwise)
    turned = np.rot90(a.rgb, k=1, axes=(0, 1))
    assert (a.aa_level > 1).mean() > 0.02  # there are edges to refine
    err = np.abs(turned - b.rgb).mean() / a.rgb.mean()
    assert err < 0.01
    assert abs((a.aa_level > 1).mean() - (b.aa_level > 1).mean()) < 0.01


def test_widths_and_thread_counts_give_the_same_image():
    scene = scene_of(disc_scene((0, 0, -1)))
    base = render(scene, aa="adaptive", simd=1, threads=1)
    for simd, threads in ((4, 3), (8, 2)):
        if simd == 8 and _core.default_width() < 8:
            continue
        r = render(scene, aa="adaptive", simd=simd, threads=threads)
        assert np.array_equal(r.rgb, base.rgb), (simd, threads)
        assert np.array_equal(r.aa_level, base.aa_level)
    assert np.isfinite(base.rgb).all() and np.isfinite(base.albedo).all()


def test_more_spp_are_more_patterns_the_same_refinement():
    scene = scene_of({**disc_scene((0, 0, -1)), "render": {"spp": 3, "integrator": "path", "max_depth": 3, "seed": 2}})
    one = render(
        scene_of({**disc_scene((0, 0, -1)), "render": {"spp": 1, "integrator": "path", "max_depth": 3, "seed": 2}}),
        aa="adaptive",
    )
    three = render(scene, aa="adaptive")
    assert np.array_equal(one.aa_level, three.aa_level)
    assert np.allclose(three.samples, 3.0, atol=1e-4)
    assert np.isfinite(three.rgb).all()


def test_scene_keys_choose_the_sampler_and_are_checked(tmp_path, capsys):
    obj = disc_scene((0, 0, -1))
    obj["render"] = {**obj["render"], "aa": "adaptive", "aa_threshold": 0.2}
    scene = scene_of(obj)
    assert scene.render.aa == "adaptive" and scene.render.aa_threshold == 0.2
    assert render(scene).aa == "adaptive"
    for bad, key in (
        ({"aa": 3}, "render.aa"),
        ({"aa": "smart"}, "render.aa"),
        ({"aa_threshold": "x"}, "render.aa_threshold"),
        ({"aa_threshold": -0.1}, "render.aa_threshold"),
    ):
        path = tmp_path / "bad.json"
        path.write_text(json.dumps({**obj, "render": {**obj["render"], **bad}}))
        assert main(["render", str(path), "--out", str(tmp_path / "x.exr"), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert key in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    with pytest.raises(ValueError, match="aa"):
        render(scene, aa="smart")
    with pytest.raises(ValueError, match="aa_threshold"):
        render(scene, aa_threshold=float("nan"))


def test_cli_options_and_the_exr_header(tmp_path, capsys):
    path = tmp_path / "s.json"
    path.write_text(json.dumps(disc_scene((0, 0, -1))))
    out = tmp_path / "a.exr"
    assert main(["render", str(path), "--out", str(out), "--aa", "adaptive", "--aa-threshold", "0.2"]) == 0
    assert "camera rays per pixel" in capsys.readouterr().out
    layers, meta = read_exr_layers(str(out))
    assert meta["patina:aa"] == "adaptive"
    assert meta["patina:aa_threshold"] == pytest.approx(0.2)
    assert 1.0 <= meta["patina:aa_rays_per_pixel"] < 4.0
    fractions = [meta[f"patina:aa_level{k}_fraction"] for k in (1, 2, 3)]
    assert sum(fractions) == pytest.approx(1.0) and fractions[0] > 0.5
    assert "aa_rays" in layers
    for option, value in (
        ("--aa", "smart"),
        ("--aa-threshold", "-1"),
        ("--aa-threshold", "nan"),
        ("--aa-threshold", "2"),
    ):
        assert main(["render", str(path), "--out", str(tmp_path / "b.exr"), option, value, "--quiet"]) == 2
        err = capsys.readouterr().err
        assert option in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "b.exr").exists()
    plain = tmp_path / "u.exr"
    assert main(["render", str(path), "--out", str(plain), "--quiet"]) == 0
    assert read_exr_layers(str(plain))[1]["patina:aa"] == "uniform"


def test_a_cancelled_adaptive_render_keeps_its_first_pass():
    prepared = PreparedScene(scene_of(disc_scene((0, 0, -1))))
    job = _core.RenderJob(prepared.core, _core.RenderOptions(spp=4, max_depth=2, seed=0, threads=1, aa="adaptive"))
    job.cancel()  # before it starts: the first pass (one pattern a pixel) still finishes
    job.start()
    job.wait()
    images = job.resolve()
    assert not job.progress().finished
    assert np.allclose(images.samples, 1.0, atol=1e-4)
    assert np.isfinite(images.rgb).all() and (images.aa_level >= 1).all()
    with pytest.raises(ValueError, match="aa"):
        _core.RenderJob(prepared.core, _core.RenderOptions(spp=1, max_depth=2, aa="smart"))
    with pytest.raises(ValueError, match="aa_threshold"):
        _core.RenderJob(prepared.core, _core.RenderOptions(spp=1, max_depth=2, aa="adaptive", aa_threshold=-1.0))


@pytest.mark.parametrize("size", [(1, 1), (33, 17)])
def test_tile_sizes_give_the_same_image(size):
    # corners are keyed by their place in the image and the decisions by position only, so
    # a corner on a tile border traced by both tiles gives both the same result
    obj = disc_scene((0, 0, -1))
    obj["camera"] = {**obj["camera"], "width": size[0], "height": size[1]}
    prepared = PreparedScene(scene_of(obj))
    images = []
    for tile in (1, 3, 16):
        job = _core.RenderJob(
            prepared.core, _core.RenderOptions(spp=2, max_depth=2, seed=0, threads=2, tile_size=tile, aa="adaptive")
        )
        job.start()
        job.wait()
        images.append(job.resolve())
    for im in images[1:]:
        assert np.array_equal(im.rgb, images[0].rgb)
    assert np.allclose(images[0].samples, 2.0, atol=1e-4)


@pytest.mark.parametrize("integrator", ["cache", "path"])
def test_with_the_cache_and_the_path_tracer_any_width_and_thread_count_give_the_same_image(integrator):
    # the refinement signal is the shared-key direct-light trace (deterministic), and the
    # cache's regions are built from their own pre-pass, once each, whichever thread asks
    scene = with_overrides(
        load_scene(materials_path("scenes", "cache-room.json")), spp=2, width=48, height=32, integrator=integrator
    )
    prepared = PreparedScene(scene)
    base = render(scene, aa="adaptive", simd=1, threads=1, prepared=prepared)
    assert (base.aa_level > 1).mean() > 0.05  # the room's edges are refined
    for simd, threads in ((4, 3), (8, 2), (16, 1)):
        if not _core.width_supported(simd):
            continue
        r = render(scene, aa="adaptive", simd=simd, threads=threads, prepared=prepared)
        assert np.array_equal(r.rgb, base.rgb), (simd, threads)
        assert np.array_equal(r.aa_level, base.aa_level)
        assert r.cache_points == base.cache_points  # the same regions, each built once
    assert np.isfinite(base.rgb).all()


def test_the_progress_says_when_the_pre_pass_runs():
    prepared = PreparedScene(scene_of(disc_scene((0, 0, -1))))
    job = _core.RenderJob(prepared.core, _core.RenderOptions(spp=1, max_depth=2, seed=0, threads=1, aa="adaptive"))
    assert not job.progress().preparing
    job.start()  # returns while the pre-pass runs on a thread of its own
    job.wait()
    assert not job.progress().preparing and job.progress().finished
