"""The radiance-cache integrators on the bundled cache scenes and in the integrating sphere
(issue 13, item 5): `cache-guided` converges to `path` (a z-test of the image mean per
scene, and in a room whose visible light all comes from later bounces), `cache` stays
within its stated bias (5 %, docs/radiance-cache.md) of a converged `path` reference, both
give the a / (1 - a) series inside a closed Lambert sphere, and neither makes a NaN, an Inf
or a negative pixel. Tiny images, so the file takes seconds; skipped where this build lacks
the integrators."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from patina.bench.convergence import integrator_missing
from patina.bundled import materials_path
from patina.render.run import render
from patina.scene.reading import load_scene, parse_scene, with_overrides
from repo_paths import ROOT

SCENES = ("cache-room", "cache-studio", "cache-ies-interior", "cache-car")
CACHE_BIAS = 0.05  # the bias docs/radiance-cache.md states for `cache` (a lit box's mean radiance)


def scene(name: str, width: int = 16) -> object:
    s = load_scene(materials_path("scenes", f"{name}.json"))
    aspect = s.camera.width / s.camera.height
    return with_overrides(s, width=width, height=round(width / aspect))


def needs(integrator: str) -> None:
    why = integrator_missing(scene("cache-studio"), integrator)
    if why is not None:
        pytest.skip(why)


def image(s: object, integrator: str, spp: int, seed: int) -> np.ndarray:
    rgb = render(with_overrides(s, integrator=integrator, spp=spp, seed=seed), threads=2).rgb.astype(np.float64)
    assert np.isfinite(rgb).all() and rgb.min() >= 0, integrator
    return rgb


@pytest.mark.parametrize("name", SCENES)
def test_cache_guided_converges_to_path(name):
    # per pixel both estimate the same value, so the differences have mean 0: a z-test of
    # their mean against its standard error from their scatter over the image's pixels
    needs("cache-guided")
    s = scene(name)
    d = (image(s, "cache-guided", 8, 11) - image(s, "path", 8, 21)).mean(axis=-1).ravel()
    z = abs(d.mean()) / (d.std(ddof=1) / math.sqrt(d.size))
    assert z < 4.0, z


def spot_room() -> object:
    """A closed Lambert room whose ceiling is lit only by later bounces: a point light just
    above the floor under an opaque plate, so the light reaches the ceiling (the camera's
    view) from the floor's bright spot, one bounce or more later -- the light the trained
    guide learns (docs/radiance-cache.md, "The trained guide")."""
    wall = {"type": "lambert", "albedo": 0.7}
    planes = [
        ([4, 4], None, [0, 0, 0]),
        ([4, 4], [[1, 0, 0], 180], [0, 2.5, 0]),
        ([4, 2.5], [[1, 0, 0], 90], [0, 1.25, -2]),
        ([4, 2.5], [[1, 0, 0], -90], [0, 1.25, 2]),
        ([2.5, 4], [[0, 0, 1], -90], [-2, 1.25, 0]),
        ([2.5, 4], [[0, 0, 1], 90], [2, 1.25, 0]),
    ]
    shapes = []
    for size, rotate, translate in planes:
        transform = {"translate": translate} if rotate is None else {"rotate": rotate, "translate": translate}
        shapes.append({"type": "plane", "material": "wall", "size": size, "transform": transform})
    for rotate, y in (([[1, 0, 0], 180], 0.3), (None, 0.3001)):  # the plate, both faces black
        transform = {"translate": [1.0, y, -1.0]} if rotate is None else {"rotate": rotate, "translate": [1.0, y, -1.0]}
        shapes.append({"type": "plane", "material": "black", "size": [0.6, 0.6], "transform": transform})
    obj = {
        "version": 1,
        "camera": {"position": [0, 1.0, 1.9], "look_at": [0, 2.0, -1.0], "fov": 70, "width": 16, "height": 12},
        "render": {"spp": 8, "integrator": "path", "max_depth": 5, "seed": 0, "cache": {"train_spp": 4}},
        "materials": {"wall": wall, "black": {"type": "lambert", "albedo": 0.0}},
        "shapes": shapes,
        "lights": [{"type": "point", "position": [1.0, 0.2, -1.0], "intensity_cd": 50}],
    }
    return parse_scene(obj, os.path.join(ROOT, "spot-room.json"))


def test_cache_guided_converges_to_path_where_the_light_comes_from_later_bounces():
    # the trained guide draws at every bounce: the z-test of the image mean where its draws
    # carry all of the light the camera sees (none of the ceiling's is direct)
    needs("cache-guided")
    s = spot_room()
    guided, path = image(s, "cache-guided", 16, 11), image(s, "path", 16, 21)
    d = (guided - path).mean(axis=-1).ravel()
    z = abs(d.mean()) / (d.std(ddof=1) / math.sqrt(d.size))
    assert z < 4.0, z


def test_cache_points_guiding_every_bounce_converge_to_path_where_the_light_comes_from_later_bounces():
    # the cache points draw at every bounce (cache.guide_bounces, docs/radiance-cache.md
    # "Guiding every bounce"): the same z-test, at the guide's probability 0.9 too, where a
    # mixture density that left the guide out would weigh the guide's draws most
    needs("cache-guided")
    path = image(spot_room(), "path", 16, 21)
    for guide in (0.5, 0.9):
        s = with_overrides(spot_room(), cache_train_passes=0, cache_guide_bounces=16, cache_guide=guide)
        d = (image(s, "cache-guided", 16, 11) - path).mean(axis=-1).ravel()
        z = abs(d.mean()) / (d.std(ddof=1) / math.sqrt(d.size))
        assert z < 4.0, (guide, z)


@pytest.mark.parametrize("name", SCENES)
def test_cache_is_within_its_stated_bias_of_a_converged_reference(name):
    needs("cache")
    s = scene(name)
    # measured at this size: the room -4.4 % against 8192 spp of path (-1.4 % against the
    # 2048 here, whose own noise on the room is about 2 %), the studio -1.5 %, the IES
    # interior 0.0 %. One 8-spp image's mean swings by +-3 % with the seed on the room (and
    # a seed in eight makes a firefly), more than the margin to the stated bias: the median
    # of five seeds' means
    reference = image(s, "path", 2048, 31).mean()
    biased = float(np.median([image(s, "cache", 8, seed).mean() for seed in range(41, 46)]))
    assert abs(biased / reference - 1) < CACHE_BIAS, (biased, reference)


ALBEDO, CANDELA = 0.5, 1000.0


def enclosure(integrator: str) -> object:
    obj = {
        "version": 1,
        "camera": {"position": [0, 0.3, 0.2], "look_at": [0.3, -0.2, -1], "fov": 60, "width": 16, "height": 12},
        # 16 segments: the series to a^15 (3e-5 short of its limit); 16 x 16 texels a cache point;
        # 16 spp: the image mean's noise (Russian roulette's) about 0.4 %, well inside 2 %
        "render": {"spp": 16, "integrator": integrator, "max_depth": 16, "seed": 3, "cache": {"resolution": 16}},
        "materials": {"wall": {"type": "lambert", "albedo": ALBEDO, "two_sided": True}},
        "shapes": [{"type": "sphere", "material": "wall", "radius": 1.0}],
        "lights": [{"type": "point", "position": [0, 0, 0], "intensity_cd": CANDELA}],
    }
    return parse_scene(obj, os.path.join(ROOT, "enclosure.json"))


@pytest.mark.parametrize("integrator", ["cache", "cache-guided"])
def test_the_closed_lambert_sphere_gives_the_a_over_1_minus_a_series(integrator):
    # wall radiance inside an integrating sphere with a point light at its centre:
    # L = a E0 / (pi (1 - a)), E0 = I / R^2 (tests/python/render/test_interreflection.py)
    needs(integrator)
    rgb = render(enclosure(integrator), threads=2).rgb
    assert np.isfinite(rgb).all()
    expected = ALBEDO * (CANDELA / 683.0) / (math.pi * (1 - ALBEDO))
    tolerance = CACHE_BIAS if integrator == "cache" else 0.02
    assert abs(float(rgb.mean()) / expected - 1) < tolerance
