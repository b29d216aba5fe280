"""Lights against analytic illuminance on a Lambert plane: spot, disk, sphere, sun, a mesh
emitter against the same quad; luminaires, alone and several with a spot (each point picking
one by its profile); photometric units (candela, cd/m^2, lux) through 683 lm/W; widths
1/4/8/16 bit-identical with every kind of light; bad light specifications."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from conftest import WIDTHS
from luminaire_field import floor_illuminance
from patina.errors import FormatError
from patina.render.run import PreparedScene, render
from patina.scene.reading import parse_scene
from repo_paths import ROOT

SIZE = 30
SUB = 6  # the exact field averaged over SUB x SUB points per pixel, as the pixels' box filter does


def plane_scene(lights: list, spp: int = 64, albedo: float = 1.0, folder: str = ROOT) -> object:
    obj = {
        "version": 1,
        "camera": {"position": [0, 6, 0.001], "look_at": [0, 0, 0], "fov": 60, "width": 40, "height": 40},
        "render": {"spp": spp, "integrator": "direct", "seed": 5},
        "materials": {"m": {"type": "lambert", "albedo": albedo}},
        "shapes": [{"type": "plane", "material": "m", "size": [SIZE, SIZE]}],
        "lights": lights,
    }
    return parse_scene(obj, os.path.join(folder, "lights.json"))


def clear_floor(r, margin: int = 2) -> np.ndarray:
    """Pixels that see only the floor: the camera is 6 m above it and the lights nearer; pixels
    within `margin` of anything nearer are left out (their samples mix floor and light)."""
    floor = np.isfinite(r.depth) & (r.depth > 5.5)
    for _ in range(margin):
        floor[1:-1, 1:-1] &= floor[:-2, 1:-1] & floor[2:, 1:-1] & floor[1:-1, :-2] & floor[1:-1, 2:]
    return floor


def plane_points(scene) -> tuple[np.ndarray, callable]:
    """Points of the plane y = 0 behind each pixel's sub-samples, and a box filter to pixels."""
    cam = scene.camera
    ys, xs = np.mgrid[0 : cam.height * SUB, 0 : cam.width * SUB] + 0.5
    d = cam.ray_direction(xs / SUB, ys / SUB)
    p = np.asarray(cam.position) + (-cam.position[1] / d[..., 1])[..., None] * d

    def box(a: np.ndarray) -> np.ndarray:
        return a.reshape(cam.height, SUB, cam.width, SUB).mean(axis=(1, 3))

    return p, box


def test_spot_light_illuminance_is_its_cone_times_cosine_over_distance_squared():
    scene = plane_scene(
        [
            {
                "type": "spot",
                "position": [0.3, 2, -0.2],
                "direction": [0.2, -1, 0.1],
                "intensity": 5,
                "inner_angle": 20,
                "outer_angle": 35,
            }
        ],
        spp=512,
    )
    r = render(scene)
    p, box = plane_points(scene)
    to = np.array([0.3, 2, -0.2]) - p
    dist2 = (to**2).sum(-1)
    axis = np.array([0.2, -1, 0.1]) / np.linalg.norm([0.2, -1, 0.1])
    c = (-to / np.sqrt(dist2)[..., None]) @ axis
    ci, co = math.cos(math.radians(20)), math.cos(math.radians(35))
    t = np.clip((c - co) / (ci - co), 0, 1)
    e = 5 * t * t * (3 - 2 * t) * (to[..., 1] / np.sqrt(dist2)) / dist2
    expected = box(e / math.pi)  # albedo 1: radiance E / pi
    lit = expected > 0.05 * expected.max()
    rel = np.abs(r.rgb[..., 0][lit] - expected[lit]) / expected[lit]
    # the pixels' jittered samples against a 6 x 6 quadrature: noise where the cone's edge crosses
    assert np.median(rel) < 5e-3 and rel.max() < 0.15
    assert abs(r.rgb[..., 0].sum() / expected.sum() - 1) < 5e-3


def disk_irradiance(rho: np.ndarray, h: float, r: float) -> np.ndarray:
    """Irradiance from a unit-radiance disc of radius r parallel to the receiver at height h, at
    radial offset rho (the configuration factor of a disc to a parallel element, times pi)."""
    a = h * h + rho * rho
    return math.pi / 2 * (1 - (a - r * r) / np.sqrt((a + r * r) ** 2 - 4 * r * r * rho * rho))


def test_disk_light_matches_the_disc_form_factor():
    scene = plane_scene(
        [{"type": "disk", "center": [0, 1.5, 0], "normal": [0, -1, 0], "radius": 0.4, "radiance": 3}], spp=256
    )
    r = render(scene)
    p, box = plane_points(scene)
    rho = np.hypot(p[..., 0], p[..., 2])
    expected = box(3 * disk_irradiance(rho, 1.5, 0.4) / math.pi)
    floor = clear_floor(r)  # the plane, not the disc's (dark) back
    got = r.rgb[..., 0][floor]
    assert abs(got.mean() / expected[floor].mean() - 1) < 0.01
    assert np.median(np.abs(got - expected[floor]) / expected[floor]) < 0.03


def test_sphere_light_is_a_point_of_its_flux_where_fully_visible():
    scene = plane_scene([{"type": "sphere", "center": [0.5, 2, 0], "radius": 0.3, "radiance": 4}], spp=512)
    r = render(scene)
    p, box = plane_points(scene)
    to = np.array([0.5, 2, 0]) - p
    d2 = (to**2).sum(-1)
    # a uniform sphere wholly above the horizon: E = pi L (R / D)^2 cos(theta)
    expected = box(4 * math.pi * 0.3**2 / d2 * (to[..., 1] / np.sqrt(d2)) / math.pi)
    floor = clear_floor(r, margin=3)
    got = r.rgb[..., 0][floor]
    assert abs(got.mean() / expected[floor].mean() - 1) < 0.01
    # area sampling of the whole sphere wastes the far half: per-pixel noise ~6 %; 4 x 4 blocks
    blocks = [(slice(y, y + 4), slice(x, x + 4)) for y in range(0, 40, 4) for x in range(0, 40, 4)]
    for b in blocks:
        if floor[b].all():
            assert abs(r.rgb[..., 0][b].mean() / expected[b].mean() - 1) < 0.05


def test_sun_lights_a_plane_by_its_irradiance_times_cosine_and_is_seen_in_the_sky():
    d = np.array([0.3, 0.8, 0.4]) / np.linalg.norm([0.3, 0.8, 0.4])
    scene = plane_scene([{"type": "sun", "direction": d.tolist(), "illuminance": 100000}], spp=16, albedo=0.5)
    r = render(scene)
    e = 100000 / 683 * d[1]  # W/m^2 of white light (luminance 1 per unit)
    assert np.allclose(r.rgb[np.isfinite(r.depth)], 0.5 / math.pi * e, rtol=2e-3)
    assert np.allclose(r.illuminance[np.isfinite(r.depth)], 100000 * d[1], rtol=2e-3)


def test_photometric_units_are_683_lumens_per_watt():
    # 1366 cd of white light is 2 W/sr: E = 2 W/sr cos / d^2, the illuminance AOV 683 x that
    scene = plane_scene([{"type": "point", "position": [0, 1, 0], "intensity_cd": 1366, "color": [1, 1, 1]}], spp=64)
    r = render(scene)
    p, box = plane_points(scene)
    to = np.array([0, 1, 0]) - p
    d2 = (to**2).sum(-1)
    e = box(2.0 * (to[..., 1] / np.sqrt(d2)) / d2)
    # exact per sample (a point light); only the pixels' jitter against the 6 x 6 quadrature
    for got, want in ((r.illuminance, 683 * e), (r.rgb[..., 1], e / math.pi)):
        rel = np.abs(got / want - 1)
        assert np.median(rel) < 0.01 and rel.max() < 0.05


def test_a_mesh_emitter_renders_as_the_quad_it_is(tmp_path):
    (tmp_path / "quad.obj").write_text("v -0.5 1 -0.3\nv 0.5 1 -0.3\nv 0.5 1 0.3\nv -0.5 1 0.3\nf 1 2 3\nf 1 3 4\n")
    quad = plane_scene(
        [{"type": "quad", "center": [0, 1, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.3], "radiance": 2}],
        spp=128,
        folder=str(tmp_path),
    )
    mesh = plane_scene([{"type": "mesh", "file": "quad.obj", "radiance": 2}], spp=128, folder=str(tmp_path))
    a, b = render(quad), render(mesh)
    floor = np.isfinite(a.depth) & (a.depth > 5) & np.isfinite(b.depth) & (b.depth > 5)
    assert abs(a.rgb[floor].mean() / b.rgb[floor].mean() - 1) < 0.01


def luminaire_file(name: str) -> str:
    return os.path.join(ROOT, "materials", "luminaires", name)


def test_every_light_kind_renders_the_same_bits_at_every_width():
    scene = plane_scene(
        [
            {"type": "point", "position": [1, 1, 1], "intensity": 1},
            {"type": "spot", "position": [-1, 2, 0], "direction": [0, -1, 0], "intensity_cd": 500},
            {"type": "disk", "center": [0, 2, 1], "normal": [0, -1, 0], "radius": 0.2, "luminance": 2000},
            {"type": "sphere", "center": [1, 1.5, -1], "radius": 0.2, "radiance": 1},
            {"type": "sun", "direction": [0.2, 1, 0.1], "irradiance": [1, 0.9, 0.8]},
            {"type": "quad", "center": [0, 3, 0], "u": [0.2, 0, 0], "v": [0, 0, 0.2], "radiance": 3},
            {"type": "luminaire", "file": luminaire_file("downlight.ies"), "position": [0.5, 2.5, 0.5]},
            {
                "type": "luminaire",
                "file": luminaire_file("floodlight.ies"),  # type B
                "position": [-1, 2, -1],
                "aim": [0.4, -1, 0.3],
            },
        ],
        spp=4,
    )
    prepared = PreparedScene(scene)
    images = [render(scene, simd=w, prepared=prepared).rgb for w in WIDTHS]
    assert np.isfinite(images[0]).all() and images[0].mean() > 0
    assert all(np.array_equal(images[0], image) for image in images[1:])


@pytest.mark.parametrize(
    ("light", "where"),
    [
        ({"type": "point", "position": [0, 1, 0], "intensity": 1, "intensity_cd": 5}, "lights[0]"),
        ({"type": "point", "position": [0, 1, 0]}, "lights[0]"),
        ({"type": "point", "position": [0, 1, 0], "intensity": 1, "color": [1, 0, 0]}, "lights[0].color"),
        ({"type": "spot", "position": [0, 1, 0], "direction": [0, 0, 0], "intensity": 1}, "lights[0].direction"),
        (
            {
                "type": "spot",
                "position": [0, 1, 0],
                "direction": [0, -1, 0],
                "intensity": 1,
                "inner_angle": 40,
                "outer_angle": 30,
            },
            "lights[0].inner_angle",
        ),
        ({"type": "disk", "center": [0, 1, 0], "normal": [0, -1, 0], "radius": 0, "radiance": 1}, "lights[0].radius"),
        ({"type": "sun", "direction": [0, 1, 0], "illuminance": -5}, "lights[0].illuminance"),
        ({"type": "sun", "direction": [0, 1, 0], "irradiance": 1, "angular_diameter": 45}, "angular_diameter"),
        ({"type": "point", "position": [0, 1, 0], "luminance": 1}, "lights[0].luminance"),
    ],
)
def test_bad_lights_name_the_key(light, where):
    with pytest.raises(FormatError) as e:
        plane_scene([light])
    assert where in str(e.value)


@pytest.mark.parametrize(
    ("file", "aim", "rotation"),
    [
        ("streetlight.ies", [0.0, -1.0, 0.0], 30.0),  # type C, asymmetric: its street side turned
        ("streetlight.ldt", [0.0, -1.0, 0.0], 30.0),  # the same table as EULUMDAT
        ("floodlight.ies", [0.3, -1.0, 0.2], 0.0),  # type B, aimed off the vertical
    ],
)
def test_luminaire_illuminance_is_its_candela_times_cosine_over_distance_squared(file, aim, rotation):
    path = luminaire_file(file)
    position = np.array([0.4, 3.0, -0.3])
    scene = plane_scene(
        [{"type": "luminaire", "file": path, "position": position.tolist(), "aim": aim, "rotation": rotation}],
        spp=64,
    )
    r = render(scene)
    p, box = plane_points(scene)
    lux = box(floor_illuminance(path, position, aim, rotation, p))
    lit = lux > 0.02 * lux.max()
    rel = np.abs(r.illuminance[lit] / lux[lit] - 1)
    assert np.median(rel) < 0.01 and abs(r.illuminance.sum() / lux.sum() - 1) < 0.01


def test_luminaires_and_a_spot_picked_by_their_profiles_add_up_to_their_illuminance():
    # each point picks a light by its intensity towards the point: the downlights' cut-off at
    # 60 degrees and the spot's cone make it pick only those that light it; the sum stays exact
    lights = [
        ("downlight.ies", [-1.5, 2.5, -1.0], [0.0, -1.0, 0.0], 0.0),
        ("downlight.ies", [1.5, 2.5, 1.0], [0.0, -1.0, 0.0], 0.0),
        ("streetlight.ies", [0.5, 3.0, -0.3], [0.0, -1.0, 0.0], 30.0),
    ]
    spot = {"position": [0.0, 2.0, 1.5], "direction": [0.3, -1.0, 0.0], "cd": 800.0, "inner": 15.0, "outer": 30.0}
    scene = plane_scene(
        [
            {"type": "luminaire", "file": luminaire_file(f), "position": at, "aim": aim, "rotation": rotation}
            for f, at, aim, rotation in lights
        ]
        + [
            {
                "type": "spot",
                "position": spot["position"],
                "direction": spot["direction"],
                "intensity_cd": spot["cd"],
                "inner_angle": spot["inner"],
                "outer_angle": spot["outer"],
            }
        ],
        spp=128,
    )
    r = render(scene)
    p, box = plane_points(scene)
    lux = sum(floor_illuminance(luminaire_file(f), at, aim, rotation, p) for f, at, aim, rotation in lights)
    out = p - np.array(spot["position"])
    d2 = (out**2).sum(-1)
    w = out / np.sqrt(d2)[..., None]
    axis = np.array(spot["direction"]) / np.linalg.norm(spot["direction"])
    ci, co = math.cos(math.radians(spot["inner"])), math.cos(math.radians(spot["outer"]))
    t = np.clip((w @ axis - co) / (ci - co), 0, 1)
    lux += spot["cd"] * t * t * (3 - 2 * t) * (-w[..., 1]) / d2
    lux = box(lux)
    lit = lux > 0.02 * lux.max()
    rel = np.abs(r.illuminance[lit] / lux[lit] - 1)
    assert np.isfinite(r.rgb).all()
    assert abs(r.illuminance.sum() / lux.sum() - 1) < 0.002
    # a point mostly lit by one light picks it nearly always: median 8e-4 at this seed
    # (selected by flux / d^2, the profile ignored: 6e-3)
    assert np.median(rel) < 0.003


def test_an_ies_tilt_table_scales_a_tilted_luminaire(tmp_path):
    from patina.photometry.writers import format_ies
    from patina.render.prepare import _luminaire
    from patina.scene.types import LuminaireLight

    tilt = (1, [0, 30, 60, 90], [1.0, 0.9, 0.75, 0.5])
    path = tmp_path / "t.ies"
    path.write_text(
        format_ies([0], [0.0, 45.0, 90.0], np.array([[300.0, 200.0, 0.0]]), tilt="INCLUDE", tilt_block=tilt)
    )

    def power(aim: list[float]) -> float:
        light = LuminaireLight(str(path), (0.0, 3.0, 0.0), tuple(aim), 0.0, 1.0, (1.0, 1.0, 1.0))
        return _luminaire(light)["power"][0]

    down = power([0, -1, 0])
    assert power([math.sin(math.radians(30)), -math.cos(math.radians(30)), 0]) == pytest.approx(0.9 * down, rel=1e-6)
    assert power([1, -1, 0]) == pytest.approx(0.825 * down, rel=1e-6)  # 45 degrees: between 0.9 and 0.75
    assert power([1, 0, 0]) == pytest.approx(0.5 * down, rel=1e-6)
