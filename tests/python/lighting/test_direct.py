"""Exact direct illuminance (patina.lighting.direct): the CIE 171:2006 point-source case,
E = I(theta) cos(theta) / d^2 to float precision for a point and for a goniometric luminaire
aimed off the vertical, one shadow ray per luminaire, the same numbers on every run; the native
sum against the double-precision sum of `arrivals` for every luminaire and sensor kind, and the
same bits at every SIMD width and thread count."""

from __future__ import annotations

import os

import numpy as np

from patina.bench.records import simd_widths
from patina.bundled import materials_path
from patina.lighting.direct import PlacedSource, arrivals, direct_illuminance
from patina.lighting.sensors import Sensors, make_sensors
from patina.render import illuminance as il
from patina.render.prepare import PreparedScene
from patina.scene.reading import parse_scene
from repo_paths import ROOT

# a rotationally symmetric type C table linear in gamma: bilinear interpolation reproduces
# I(gamma) = 1000 - 5 gamma (degrees) exactly, so the expected lux needs no interpolation
GAMMAS = np.arange(0, 181, 10.0)


def linear_cd(gamma_deg: np.ndarray) -> np.ndarray:
    return 1000.0 - 5.0 * np.asarray(gamma_deg)


def write_ies(folder: str) -> str:
    path = os.path.join(folder, "linear.ies")
    lines = [
        "IESNA:LM-63-2002",
        "[TEST] candela linear in gamma",
        "TILT=NONE",
        f"1 -1 1 {len(GAMMAS)} 1 1 2 0 0 0",
        "1 1 0",
        " ".join(f"{g:g}" for g in GAMMAS),
        "0",
        " ".join(f"{c:g}" for c in linear_cd(GAMMAS)),
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def scene(folder: str, lights: list, shapes: list | None = None):
    obj = {
        "version": 1,
        "camera": {"position": [0, 5, 5], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "materials": {"m": {"type": "lambert", "albedo": 0.5}},
        "shapes": [{"type": "plane", "material": "m", "size": [40, 40]}] + (shapes or []),
        "lights": lights,
    }
    return parse_scene(obj, os.path.join(folder, "scene.json"))


def test_a_goniometric_luminaire_aimed_askew_gives_i_cos_over_d2_to_float_precision(tmp_path):
    write_ies(str(tmp_path))
    position, aim = np.array([0.5, 3.0, -1.0]), np.array([0.3, -1.0, 0.2])
    light = {"type": "luminaire", "file": "linear.ies", "position": position.tolist(), "aim": aim.tolist()}
    s = scene(str(tmp_path), [light])
    grid = il.parse_grid("-4,-4,4,4,17,17", height=0.0)
    report = il.compute(s, grid, samples=1)
    _, _, pts = grid.points()
    to_light = position - pts.astype(np.float64)
    d = np.linalg.norm(to_light, axis=1)
    gamma = np.degrees(np.arccos(np.clip((-to_light / d[:, None]) @ (aim / np.linalg.norm(aim)), -1, 1)))
    expected = linear_cd(gamma) * (to_light[:, 1] / d) / d**2
    np.testing.assert_allclose(report.lux.ravel(), expected, rtol=2e-5)  # float32 table and angles
    assert report.exact_lights == 1


def test_exact_direct_is_deterministic_and_independent_of_the_samples_asked(tmp_path):
    lights = [{"type": "point", "position": [x, 2.8, z], "intensity_cd": 800} for x in (-1.5, 1.5) for z in (-1, 1)]
    s = scene(str(tmp_path), lights)
    grid = il.parse_grid("-3,-2,3,2,13,9", height=0.8)
    runs = [il.compute(s, grid, samples=n).lux for n in (1, 16, 256)]
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[1], runs[2])


def test_a_panel_between_light_and_sensor_casts_a_sharp_shadow(tmp_path):
    blocker = {"type": "plane", "material": "m", "size": [1, 1], "transform": {"translate": [0, 1.5, 0]}}
    s = scene(str(tmp_path), [{"type": "point", "position": [0, 3, 0], "intensity_cd": 1000}], [blocker])
    grid = il.parse_grid("-2,0,2,0,41,1", height=0.0)
    lux = il.compute(s, grid, samples=1).lux.ravel()
    x = np.linspace(-2, 2, 41)
    shadowed = np.abs(x) < 0.95  # the panel's shadow on the floor spans |x| < 1 (twice its half-width)
    clear = np.abs(x) > 1.05
    assert np.all(lux[shadowed] == 0)
    d2 = x[clear] ** 2 + 9
    np.testing.assert_allclose(lux[clear], 1000 * 3 / d2**1.5, rtol=2e-5)


def test_per_source_sums_to_the_total_and_a_spot_follows_its_smoothstep_cone():
    spot = PlacedSource.of(
        parse_scene(
            {
                "version": 1,
                "camera": {"position": [0, 5, 5], "look_at": [0, 0, 0]},
                "materials": {},
                "shapes": [],
                "lights": [
                    {
                        "type": "spot",
                        "position": [0, 2, 0],
                        "direction": [0, -1, 0],
                        "intensity_cd": 500,
                        "inner_angle": 10,
                        "outer_angle": 30,
                    },
                    {"type": "point", "position": [1, 2, 0], "intensity_cd": 100},
                ],
            },
            os.path.join(ROOT, "s.json"),
        ).lights[0]
    )
    pts = np.array([[0.0, 0, 0], [2 * np.tan(np.radians(20)), 0, 0], [2 * np.tan(np.radians(35)), 0, 0]])
    lux = direct_illuminance([spot], Sensors.horizontal(pts))
    cos_t = np.cos(np.radians([0, 20, 35]))
    t = np.clip((cos_t - np.cos(np.radians(30))) / (np.cos(np.radians(10)) - np.cos(np.radians(30))), 0, 1)
    expected = 500 * t * t * (3 - 2 * t) * cos_t**3 / 4
    np.testing.assert_allclose(lux, expected, rtol=2e-6)  # the float32 kernel
    assert lux[2] == 0 and 0 < lux[1] < lux[0]


SENSOR_KINDS = (("up", None), ("vertical", 30.0), ("cylindrical", None), ("semicylindrical", 120.0))


def test_a_point_source_gives_i_cos_over_d2_to_float_precision_at_every_width():
    position = np.array([0.7, 2.5, -0.4])
    src = PlacedSource.of(
        scene(ROOT, [{"type": "point", "position": position.tolist(), "intensity_cd": 800}]).lights[0]
    )
    x, z = np.meshgrid(np.linspace(-6, 6, 41), np.linspace(-5, 5, 37))
    pts = np.stack([x.ravel(), np.zeros(x.size), z.ravel()], axis=1)
    to_light = position - pts
    d2 = np.einsum("ij,ij->i", to_light, to_light)
    for w in simd_widths():
        lux = direct_illuminance([src], Sensors.horizontal(pts), width=w)
        np.testing.assert_allclose(lux, 800 * to_light[:, 1] / d2**1.5, rtol=2e-6)


def luminaire_room():
    """Point, spot and goniometric luminaires (IES type C, EULUMDAT, IES type B aimed askew)
    over a floor with spheres and a panel in the way."""
    files = {name: os.path.join(materials_path(), "luminaires", name) for name in ("downlight.ies", "streetlight.ldt")}
    flood = os.path.join(materials_path(), "luminaires", "floodlight.ies")
    lights = [
        {"type": "luminaire", "file": files["downlight.ies"], "position": [-3, 3, -2]},
        {"type": "luminaire", "file": files["streetlight.ldt"], "position": [3, 4, 1], "rotation": 30},
        {"type": "luminaire", "file": flood, "position": [0, 5, 6], "aim": [0.2, -1, -0.8]},
        {
            "type": "spot",
            "position": [1, 2.5, -3],
            "direction": [0.3, -1, 0.2],
            "intensity_cd": 900,
            "inner_angle": 15,
            "outer_angle": 40,
        },
        {"type": "point", "position": [-1, 2.8, 2], "intensity_cd": 600},
    ]
    shapes = [
        {"type": "sphere", "material": "m", "radius": 0.5, "transform": {"translate": [-2 + 2 * k, 1.0, k - 1]}}
        for k in range(3)
    ]
    shapes.append({"type": "plane", "material": "m", "size": [2, 2], "transform": {"translate": [2.5, 2.0, 0.5]}})
    return scene(ROOT, lights, shapes)


def room_sensors(name: str, azimuth: float | None, n: int = 3001) -> Sensors:
    rng = np.random.default_rng(5)
    pts = np.stack([rng.uniform(-6, 6, n), rng.uniform(0.0, 1.5, n), rng.uniform(-6, 6, n)], axis=1)
    return make_sensors(pts, name, azimuth)


def test_the_native_sum_agrees_with_the_double_precision_sum_for_every_luminaire_and_sensor_kind():
    s = luminaire_room()
    sources, prepared = [PlacedSource.of(light) for light in s.lights], PreparedScene(s)
    offset = il.ray_offset(prepared)
    for kind in SENSOR_KINDS:
        sensors = room_sensors(*kind)
        native = direct_illuminance(sources, sensors, prepared.accel, offset, per_source=True)
        a = arrivals(sources, sensors.points, prepared.accel, offset)
        reference = np.zeros_like(native)
        for i in range(len(sources)):
            lux = a.candela[i] * sensors.response(a.towards[i])
            np.divide(lux, a.d2[i], out=reference[i], where=a.candela[i] > 0)
        # float precision of the illuminance the source's brightest direction would give here: the
        # float angles move a steep table's value (a cut-off) further, relatively, than its peak's
        scale = a.candela.max(axis=1, keepdims=True) / a.d2
        assert np.all(np.abs(native - reference) <= 5e-6 * scale), kind
        assert np.count_nonzero(reference) > 0.3 * reference.size, kind
        assert np.any((direct_illuminance(sources, sensors, None, offset, per_source=True) > 0) & (native == 0))


def test_every_width_and_thread_count_gives_the_scalar_paths_bits():
    s = luminaire_room()
    sources, prepared = [PlacedSource.of(light) for light in s.lights], PreparedScene(s)
    for kind in SENSOR_KINDS:
        sensors = room_sensors(*kind)
        args = sources, sensors, prepared.accel, il.ray_offset(prepared)
        scalar = direct_illuminance(*args, per_source=True, width=1, threads=1)
        for w in simd_widths():
            for threads in (1, 2):
                wide = direct_illuminance(*args, per_source=True, width=w, threads=threads)
                assert np.array_equal(wide, scalar), (kind, w, threads)
