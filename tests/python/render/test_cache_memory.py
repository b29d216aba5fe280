"""The radiance cache's memory estimate (patina.render.cache_memory): what `patina render`
states before work for settings whose cache regions outgrow the regions' budget."""

from __future__ import annotations

import os

from patina.cli import main
from patina.native import _core
from patina.render.cache_memory import (
    CACHE_BYTES_PER_TEXEL,
    cache_memory,
    cache_memory_notice,
    cache_region_bytes,
    regions_held,
)
from patina.scene.reading import load_scene, with_overrides
from repo_paths import ROOT

CACHE_ROOM = os.path.join(ROOT, "materials", "scenes", "cache-room.json")


def room(**overrides):
    return with_overrides(load_scene(CACHE_ROOM), **overrides)


def test_a_region_holds_a_cache_point_a_block_of_r_squared_texels():
    pixels = _core.cache_region_pixels
    assert cache_region_bytes(64, 1) == pixels**2 * CACHE_BYTES_PER_TEXEL * 64**2
    assert cache_region_bytes(64, 8) == (pixels // 8) ** 2 * CACHE_BYTES_PER_TEXEL * 64**2
    assert cache_region_bytes(24, 5) == 7**2 * CACHE_BYTES_PER_TEXEL * 24**2  # 32 pixels: 6 blocks and a part
    assert cache_region_bytes(64, 8, hemispheres=True) == (pixels // 8) ** 2 * (CACHE_BYTES_PER_TEXEL + 12) * 64**2


def test_the_estimate_is_the_budget_plus_the_regions_of_a_thread_and_nothing_without_a_cache():
    budget = _core.cache_region_budget_bytes
    # a 32-pixel tile (the adaptive sampler's) within a block of 4 pixels reaches 3 x 3
    # regions, a 16-pixel one 2 x 2; and one more is built
    scene = room(integrator="cache", cache_resolution=32, cache_block=4, aa="adaptive")
    assert regions_held(scene) == 9
    assert regions_held(room(integrator="cache", cache_block=4)) == 4
    assert cache_memory(scene, 3) == budget + 3 * 10 * cache_region_bytes(32, 4, hemispheres=True)
    guided = room(integrator="cache-guided")  # no hemispheres taken across a tile's edge: its region alone
    assert regions_held(guided) == 1
    assert cache_memory(guided, 1) == budget + 2 * cache_region_bytes(24, guided.render.cache.block)
    assert cache_memory(room(integrator="path"), 8) == 0


def test_default_settings_say_nothing_and_large_points_at_small_blocks_are_announced():
    assert cache_memory_notice(room(integrator="cache"), 2) is None
    notice = cache_memory_notice(room(integrator="cache", cache_resolution=128, cache_block=1), 2)
    assert notice is not None and "GiB" in notice and "resolution 128" in notice and "block 1" in notice
    assert "--cache-block" in notice


def test_render_prints_the_notice_before_rendering(tmp_path, capsys):
    out = tmp_path / "r.png"
    args = ["render", CACHE_ROOM, "--integrator", "cache", "--cache-resolution", "96", "--cache-block", "1"]
    assert main([*args, "--spp", "1", "--width", "8", "--height", "6", "--threads", "1", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert err.count("radiance cache: may take up to") == 1 and "(1 threads here)" in err
    assert out.exists()
