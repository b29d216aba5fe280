"""Illuminance with interreflections (`patina illuminance --indirect`, the indirect
illuminance AOV) against the integrating sphere.

Inside a closed Lambert sphere of albedo a and radius R with an isotropic point light of
intensity I at its centre, every wall point receives the direct illuminance E0 = I / R^2.
The sphere's property (the form factor from any surface element to another is dA' / A)
makes each reflection of a flux spread uniformly over the wall: the k-th reflection adds a
uniform a^k E0, so the wall radiance is uniform, L = a E_wall / pi, and any sensor inside
(any facing, anywhere but at the light) sees that radiance over its whole hemisphere. The
indirect illuminance there is therefore the series

    E_indirect = E0 (a + a^2 + ... + a^D)  ->  E0 a / (1 - a)

for light of at most D reflections, and a camera inside sees L = a E0 / (pi (1 - a)) on every
wall. The mesh sphere is a polyhedron (64 rings): its faces are within 0.12 % of R, so the
tolerances below are a little wider than the noise alone would allow.
"""

from __future__ import annotations

import json
import os

import numpy as np
import pytest

from conftest import WIDTHS
from patina.cli import main
from patina.render import illuminance as il
from patina.render.run import render
from patina.scene.reading import parse_scene, with_overrides
from repo_paths import ROOT

ALBEDO = 0.5
CANDELA = 1000.0  # at R = 1 m: E0 = 1000 lux


def enclosure(max_depth: int = 64, spp: int = 8, albedo: float = ALBEDO) -> object:
    obj = {
        "version": 1,
        "camera": {"position": [0, 0.3, 0.2], "look_at": [0.3, -0.2, -1], "fov": 60, "width": 16, "height": 12},
        "render": {"spp": spp, "integrator": "path", "max_depth": max_depth, "seed": 3},
        "materials": {"wall": {"type": "lambert", "albedo": albedo, "two_sided": True}},
        "shapes": [{"type": "sphere", "material": "wall", "radius": 1.0}],
        "lights": [{"type": "point", "position": [0, 0, 0], "intensity_cd": CANDELA}],
    }
    return parse_scene(obj, os.path.join(ROOT, "enclosure.json"))


GRID = il.parse_grid("-0.4,-0.4,0.4,0.4,3,3", height=-0.2)


def test_sensors_inside_the_sphere_get_the_a_over_1_minus_a_series():
    direct = il.compute(enclosure(), GRID, samples=16)
    total = il.compute(enclosure(), GRID, samples=8192, indirect=True)
    # direct: I cos / d^2 from the centre, exact per sensor
    _, _, pts = GRID.points()
    d2 = (pts**2).sum(1)
    assert np.allclose(direct.lux.ravel(), CANDELA * (-pts[:, 1] / np.sqrt(d2)) / d2, rtol=1e-4)
    indirect = total.lux - direct.lux
    expected = CANDELA * ALBEDO / (1 - ALBEDO)
    # per sensor about 0.6 % noise (Russian roulette), the mean of 9 about 0.2 %
    assert np.all(np.abs(indirect / expected - 1) < 0.03), indirect
    assert abs(indirect.mean() / expected - 1) < 0.01
    # sensors facing down see the same uniform wall
    down = il.parse_grid("-0.4,-0.4,0.4,0.4,3,3", height=0.2, facing="down")
    indirect_down = il.compute(enclosure(), down, samples=8192, indirect=True).lux - il.compute(enclosure(), down).lux
    assert abs(indirect_down.mean() / expected - 1) < 0.01


@pytest.mark.parametrize("max_depth", [2, 3, 4])
def test_the_series_stops_at_the_scenes_max_depth(max_depth):
    # max_depth segments (Mitsuba's convention): a sensor sees light of max_depth - 1 reflections
    grid = il.parse_grid("0,0,0,0,1,1", height=0.0)
    s = enclosure(max_depth=max_depth)
    indirect = il.compute(s, grid, samples=4096, indirect=True).lux - il.compute(s, grid).lux
    series = sum(ALBEDO**k for k in range(1, max_depth))
    assert float(indirect[0, 0]) == pytest.approx(CANDELA * series, rel=0.005)


def test_black_walls_reflect_nothing():
    s = enclosure(albedo=0.0)
    grid = il.parse_grid("-0.4,-0.4,0.4,0.4,3,3", height=0.0)
    assert np.array_equal(il.compute(s, grid, samples=64, indirect=True).lux, il.compute(s, grid, samples=64).lux)


def test_indirect_illuminance_is_the_same_bits_at_every_width_and_thread_count():
    s = enclosure(max_depth=8)
    ref = il.compute(s, GRID, samples=64, indirect=True, width=1, threads=1).lux
    for width in WIDTHS:
        for threads in (1, 2):
            assert np.array_equal(il.compute(s, GRID, samples=64, indirect=True, width=width, threads=threads).lux, ref)


def test_the_aov_counts_interreflections_and_the_image_stays_the_same():
    on = with_overrides(enclosure(spp=32), indirect_illuminance=True)
    plain = render(enclosure(spp=32), threads=1)
    lit = render(on, threads=1)
    e0 = CANDELA
    # the image does not change (the sensor paths draw numbers of their own)
    assert np.array_equal(plain.rgb, lit.rgb)
    # every pixel sees the wall, where the direct illuminance is E0 within the mesh's sag
    assert np.all(np.abs(plain.illuminance / e0 - 1) < 0.003)
    total = e0 / (1 - ALBEDO)
    assert abs(float(lit.illuminance.mean()) / total - 1) < 0.01
    assert np.all(np.abs(lit.illuminance / total - 1) < 0.25)  # 32 sensor paths a pixel: 4 % noise
    # the beauty: the furnace of the path tracer itself, L = a E0 / (pi (1 - a)) in W/(m^2 sr)
    radiance = ALBEDO * (CANDELA / 683.0) / (np.pi * (1 - ALBEDO))
    assert abs(float(plain.rgb.mean()) / radiance - 1) < 0.01


def test_the_aov_is_the_same_bits_at_every_width_and_thread_count():
    on = with_overrides(enclosure(max_depth=6, spp=2), indirect_illuminance=True)
    ref = render(on, threads=1, simd=1).illuminance
    for width in WIDTHS:
        for threads in (1, 2):
            assert np.array_equal(render(on, threads=threads, simd=width).illuminance, ref)


def test_cli_indirect_reports_the_total(capsys):
    street = os.path.join(ROOT, "materials", "scenes", "street-luminaire.json")
    args = ["illuminance", street, "--grid=-3.5,-15,3.5,15,4,8", "--samples", "8", "--json"]
    assert main(args) == 0
    direct = json.loads(capsys.readouterr().out)
    assert main([*args, "--indirect"]) == 0
    total = json.loads(capsys.readouterr().out)
    assert total["interreflections"] is True and direct["interreflections"] is False
    # per sensor the same direct estimate plus a sum of non-negative path estimates
    assert np.all(np.array(total["lux"]) >= np.array(direct["lux"]))
    assert main([*args[:-1], "--indirect"]) == 0
    assert "total illuminance" in capsys.readouterr().out
