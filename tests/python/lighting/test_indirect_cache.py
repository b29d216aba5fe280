"""Indirect illuminance from the radiance cache (patina.lighting.indirect_cache and
`_core.sensor_cache_points`): a cache point's hemisphere gives the same bits at every SIMD
width, sensor by sensor, and the same lux as the sensor paths (an unbiased estimate: the
equal-area texels' plain sum); its reuse radius is the harmonic mean of real hit distances;
the sensors of a grid gather from far fewer cache points within a few percent of the paths."""

from __future__ import annotations

import numpy as np

from patina.bench.lighting import INDIRECT_SCENE, office_sensors, path_indirect
from patina.bench.records import simd_widths
from patina.bundled import materials_path
from patina.lighting.indirect_cache import CacheSettings, cached_indirect
from patina.native import _core
from patina.render.illuminance import sensor_depth
from patina.render.prepare import PreparedScene
from patina.scene.reading import load_scene


def office():
    scene = load_scene(materials_path("scenes", f"{INDIRECT_SCENE}.json"))
    return PreparedScene(scene), sensor_depth(scene)


def paths(prepared, points, normals, samples, depth):
    return path_indirect(prepared, points, normals, samples, 3, depth)


def test_every_width_gives_the_scalar_paths_bits_sensor_by_sensor():
    prepared, depth = office()
    points, normals = office_sensors(0.7)  # 9 x 6 sensors: a last packet part full
    normals[::3] = [1.0, 0.0, 0.0]  # some facing a wall
    one = _core.sensor_cache_points(prepared.core, points, normals, 4, 5, 1, 1, depth)
    for w in simd_widths():
        wide = _core.sensor_cache_points(prepared.core, points, normals, 4, 5, w, 2, depth)
        for a, b in zip(one, wide):
            np.testing.assert_array_equal(np.asarray(a).view(np.int32), np.asarray(b).view(np.int32), f"width {w}")


def test_a_cache_points_lux_is_the_sensor_paths_and_its_radius_a_real_distance():
    prepared, depth = office()
    points = np.ascontiguousarray([[0.0, 0.75, 0.0], [-2.6, 0.75, 1.6], [1.0, 1.2, -1.9]], np.float32)
    normals = np.ascontiguousarray([[0, 1, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    built = _core.sensor_cache_points(prepared.core, points, normals, 48, 1, 0, 0, depth)
    lux, radius = (np.asarray(a, np.float64) for a in built)
    want = paths(prepared, points, normals, 8192, depth)
    # 2304 texel paths against 8192 sensor paths: a few percent of noise at most (measured 0.1 to 1.2 %)
    np.testing.assert_allclose(lux, want, rtol=0.04)
    # the room is 6 x 4 m and 3 m high (the scene): every hit lies within its diagonal
    assert np.all((radius > 0.05) & (radius < 7.9))


def test_a_grid_gathers_from_far_fewer_cache_points_within_a_few_percent():
    prepared, depth = office()
    points, normals = office_sensors(0.25)
    result = cached_indirect(prepared.core, points, normals, CacheSettings(depth, 0, 16))
    want = paths(prepared, points, normals, 2048, depth)
    assert len(result.cache_points) < len(points) / 2  # measured 118 of 384
    relative = result.lux / want - 1
    assert abs(relative.mean()) < 0.02  # the bias docs/lighting.md measures: +0.5 %
    assert np.sqrt(np.mean(relative**2)) < 0.06  # measured 2.7 %, the reference's noise included
