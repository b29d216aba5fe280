"""The Patina -> Mitsuba 3 converter means what docs/scene.md says: the same camera rays, the
same lat-long lookup, and renders that match analytic answers (white furnace, a Lambert plane
under a point light and under a quad light)."""

from __future__ import annotations

import json
import math
import os
import shutil

import numpy as np
import pytest

mi = pytest.importorskip("mitsuba")

import trimesh  # noqa: E402

from luminaire_field import floor_illuminance  # noqa: E402
from patina.photometry.luminaire import load_luminaire  # noqa: E402
from patina.photometry.placement import rgb_per_candela  # noqa: E402
from patina.photometry.writers import format_ies  # noqa: E402
from patina.scene.mitsuba import MitsubaConversionError, bsdf, quad_to_world, to_mitsuba  # noqa: E402
from patina.scene.reading import load_scene, parse_scene, with_overrides  # noqa: E402
from patina.scene.types import CarpaintMaterial, Coat, LambertMaterial  # noqa: E402
from scene_helpers import ROOT, referenced_files  # noqa: E402


@pytest.fixture(autouse=True)
def scalar_rgb():
    mi.set_variant("scalar_rgb")


def scene(folder, **parts):
    obj = {"version": 1, "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 32, "height": 24}}
    obj.update(parts)
    return parse_scene(obj, os.path.join(str(folder), "scene.json"))


def render(s, meshes=None) -> np.ndarray:
    image = np.asarray(mi.render(mi.load_dict(to_mitsuba(s, meshes))), np.float64)
    assert image.shape == (s.camera.height, s.camera.width, 3)
    assert np.isfinite(image).all()
    return image


def icosphere():
    m = trimesh.creation.icosphere(subdivisions=3)
    return np.asarray(m.vertices), np.asarray(m.faces), np.asarray(m.vertex_normals)


# --- geometry and conventions --------------------------------------------------------------


@pytest.mark.parametrize("camera_type", ["pinhole", "thinlens"])
def test_camera_rays_match(tmp_path, camera_type):
    camera = {"type": camera_type, "position": [1, 2, 3], "look_at": [-0.5, 0.3, -1], "up": [0.2, 1, 0],
              "fov": 47, "width": 40, "height": 30}  # fmt: skip
    s = scene(tmp_path, camera=camera)
    sensor = mi.load_dict(to_mitsuba(s)["sensor"])
    for i, j in [(0, 0), (39, 0), (0, 29), (20, 15), (7, 22)]:
        x, y = i + 0.5, j + 0.5
        ray, _ = sensor.sample_ray(0.0, 0.5, [x / 40, y / 30], [0.5, 0.5])  # the lens centre for a thin lens
        assert np.allclose(np.array(ray.d), s.camera.ray_direction(x, y), atol=1e-5)
        assert np.allclose(np.cross(np.array(ray.o) - s.camera.position, np.array(ray.d)), 0, atol=1e-5)


@pytest.mark.parametrize("rotation", [0.0, 70.0, -150.0])
def test_envmap_reads_the_same_texel(tmp_path, rotation):
    """Mitsuba's envmap, turned by our rotation, shows texel (u, v) in the direction our convention gives."""
    blocks = np.random.default_rng(5).uniform(0.1, 1.0, (4, 8, 3)).astype(np.float32)
    texels = np.kron(blocks, np.ones((8, 8, 1), np.float32))  # 32 x 64, blocks of 8 x 8 texels
    path = tmp_path / "env.exr"
    mi.Bitmap(texels).write(str(path))
    s = scene(tmp_path, environment={"type": "map", "file": "env.exr", "rotation": rotation, "intensity": 2})
    emitter = mi.load_dict(to_mitsuba(s)).environment()
    for row in range(4):
        for col in range(8):
            u, v = (col + 0.5) / 8, (row + 0.5) / 4  # block centres: away from every filter edge
            si = mi.SurfaceInteraction3f()
            si.wi = mi.Vector3f(*(-s.environment.direction(u, v)))
            assert np.allclose(np.array(emitter.eval(si)), 2 * blocks[row, col], rtol=1e-4)


def test_quad_frame():
    s = parse_scene(
        {"version": 1, "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},
         "lights": [{"type": "quad", "center": [1, 2, 3], "u": [0.5, 0, 0], "v": [0, 0, 0.25], "radiance": 1}]},
        "x.json",
    )  # fmt: skip
    m = quad_to_world(s.lights[0])
    assert np.allclose(m @ [1, 1, 0, 1], [1.5, 2, 3.25, 1])
    assert np.allclose(m[:3, 2], [0, -1, 0]) and np.allclose(quad_to_world(s.lights[0], flip=True)[:3, 2], [0, 1, 0])


# --- renders against analytic answers ----------------------------------------------------------


@pytest.mark.parametrize("with_mesh", [False, True])
def test_white_furnace(tmp_path, with_mesh):
    """An albedo-1 Lambert sphere under constant radiance L renders L (the mean over the sphere, within noise)."""
    radiance = np.array([0.7, 0.5, 0.3])
    s = scene(
        tmp_path,
        render={"spp": 64, "integrator": "path", "max_depth": 64},
        materials={"white": {"type": "lambert", "albedo": 1}},
        shapes=[{"type": "sphere", "material": "white", "transform": {"scale": 1.2}}],
        environment={"type": "constant", "radiance": radiance.tolist()},
    )
    image = render(s, {0: icosphere()} if with_mesh else None)
    i, j = np.meshgrid(np.arange(32) + 0.5, np.arange(24) + 0.5)
    d = s.camera.ray_direction(i, j)
    closest = np.linalg.norm(np.cross(d, -np.asarray(s.camera.position)), axis=-1)  # ray to sphere-centre distance
    on_sphere, background = closest < 1.1, closest > 1.25
    assert on_sphere.sum() > 300 and background.sum() > 50
    assert np.allclose(image[background], radiance, rtol=1e-5)
    assert np.allclose(image[on_sphere].mean(axis=0), radiance, rtol=0.01)


def _plane_hits(s, samples: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """Points on y = 0 seen through each pixel, `samples`^2 per pixel: (H, W, samples^2, 3) and the ray validity."""
    w, h = s.camera.width, s.camera.height
    offsets = (np.arange(samples) + 0.5) / samples
    x = np.arange(w)[None, :, None, None] + offsets[None, None, :, None]
    y = np.arange(h)[:, None, None, None] + offsets[None, None, None, :]
    x, y = np.broadcast_arrays(x, y)
    d = s.camera.ray_direction(x, y).reshape(h, w, samples * samples, 3)
    t = -s.camera.position[1] / d[..., 1]
    return np.asarray(s.camera.position) + t[..., None] * d, t > 0


def _point_light_check(s, image: np.ndarray) -> None:
    """Radiance = albedo / pi * I cos(theta) / d^2 at every visible point of the plane y = 0."""
    albedo = np.asarray(s.materials[s.shapes[0].material].albedo)
    light = s.lights[0]
    points, valid = _plane_hits(s, 16)
    assert valid.all()
    to_light = np.asarray(light.position) - points
    d2 = (to_light**2).sum(-1)
    irradiance = np.asarray(light.intensity) * (to_light[..., 1] / np.sqrt(d2) / d2)[..., None]
    expected = (albedo / math.pi * irradiance).mean(axis=2)
    # the only noise is where in its pixel each of the 512 rays goes: about 1 % at the far edge
    relative = np.abs(image / expected - 1)
    assert relative.max() < 0.02 and relative.mean() < 0.005


@pytest.mark.parametrize("with_mesh", [False, True])
def test_lambert_plane_under_point_light(tmp_path, with_mesh):
    s = scene(
        tmp_path,
        camera={"position": [0, 4, 4], "look_at": [0, 0, 0], "fov": 40, "width": 32, "height": 24},
        render={"spp": 512, "integrator": "direct"},
        materials={"grey": {"type": "lambert", "albedo": [0.5, 0.4, 0.3]}},
        shapes=[{"type": "plane", "material": "grey", "size": [30, 30]}],
        lights=[{"type": "point", "position": [0.5, 2.0, -0.5], "intensity": [10.0, 6.0, 3.0]}],
    )
    mesh = (np.array([[-15, 0, -15], [15, 0, -15], [15, 0, 15], [-15, 0, 15]]), np.array([[0, 2, 1], [0, 3, 2]]), None)
    _point_light_check(s, render(s, {0: mesh} if with_mesh else None))


def test_bundled_lambert_plane_point(tmp_path):
    s = with_overrides(load_scene(os.path.join(ROOT, "materials", "scenes", "lambert-plane-point.json")), spp=512)
    s = with_overrides(s, width=s.camera.width // 4, height=s.camera.height // 4)
    _point_light_check(s, render(s))


@pytest.mark.parametrize("name", ["diffuse-sphere", "conductor-sphere", "area-box"])
def test_bundled_cross_check_scenes_convert(tmp_path, name):
    """With a stand-in environment map (uniform 1), the bundled cross-check scenes render in Mitsuba."""
    target = tmp_path / "materials" / "scenes" / f"{name}.json"
    target.parent.mkdir(parents=True)
    shutil.copy(os.path.join(ROOT, "materials", "scenes", f"{name}.json"), target)
    for file in referenced_files(json.loads(target.read_text())):
        path = target.parent / file
        path.parent.mkdir(parents=True, exist_ok=True)
        mi.Bitmap(np.ones((8, 16, 3), np.float32)).write(str(path))
    s = with_overrides(load_scene(target), width=16, height=12, spp=4)
    image = render(s)
    assert image.min() >= 0 and image.max() > 0
    if name != "area-box":  # the corner sees the stand-in sky
        assert np.allclose(image[0, 0], 1.0)


def _polygon_irradiance(points: np.ndarray, corners: np.ndarray, radiance: float) -> np.ndarray:
    """Irradiance on an up-facing surface at `points` from a uniform Lambertian polygon (Lambert's formula)."""
    total = np.zeros(points.shape[:-1])
    for k in range(len(corners)):
        a = corners[k] - points
        b = corners[(k + 1) % len(corners)] - points
        a /= np.linalg.norm(a, axis=-1, keepdims=True)
        b /= np.linalg.norm(b, axis=-1, keepdims=True)
        c = np.cross(a, b)
        angle = np.arccos(np.clip((a * b).sum(-1), -1, 1))
        total += angle * c[..., 1] / np.linalg.norm(c, axis=-1)
    return radiance / 2 * np.abs(total)


@pytest.mark.parametrize(("v_z", "two_sided", "lit"), [(0.3, False, True), (-0.3, False, False), (-0.3, True, True)])
def test_lambert_plane_under_quad_light(tmp_path, v_z, two_sided, lit):
    """The quad emits on the side of u x v only (or both if two-sided), with the analytic irradiance.

    The light hangs behind the camera (out of view, casting no shadow on what is seen).
    """
    albedo, radiance = 0.6, 4.0
    center, u, v = np.array([0.2, 1.0, 3.5]), np.array([0.4, 0, 0]), np.array([0, 0, v_z])
    s = scene(
        tmp_path,
        camera={"position": [0, 3, 3], "look_at": [0, 0, 0], "fov": 30, "width": 24, "height": 16},
        render={"spp": 1024, "integrator": "direct"},
        materials={"grey": {"type": "lambert", "albedo": albedo}},
        shapes=[{"type": "plane", "material": "grey", "size": [30, 30]}],
        lights=[{"type": "quad", "center": center.tolist(), "u": u.tolist(), "v": v.tolist(), "radiance": radiance,
                 "two_sided": two_sided}],
    )  # fmt: skip
    assert np.allclose(s.lights[0].normal, [0, -1, 0] if v_z > 0 else [0, 1, 0])
    image = render(s)
    if not lit:
        assert image.max() == 0
        return
    points, _ = _plane_hits(s, 4)
    corners = np.array([center - u - v, center + u - v, center + u + v, center - u + v])
    expected = (albedo / math.pi * _polygon_irradiance(points, corners, radiance)).mean(axis=2)
    grey = image.mean(axis=2)
    assert np.allclose(image, grey[..., None], rtol=1e-5)  # a grey light on a grey plane
    assert grey.mean() == pytest.approx(expected.mean(), rel=0.01)
    # per pixel: 1024 area-uniform light samples (half on the dark back rectangle when two-sided), 2-9 % seen
    assert np.abs(grey - expected).max() < 0.15 * expected.max()


# --- materials and what cannot be converted ---------------------------------------------------


def test_material_dictionaries(tmp_path):
    s = scene(
        tmp_path,
        materials={
            "au": {"type": "conductor", "metal": "Au", "roughness": [0.2, 0.1], "tint": 0.9, "two_sided": True},
            "mirror": {"type": "conductor", "eta": 1.5, "k": 3, "roughness": 0},
            "glass": {"type": "dielectric", "eta": 1.33, "roughness": 0.1},
        },
        shapes=[{"type": "sphere", "material": m} for m in ("au", "mirror", "glass")],
    )
    d = to_mitsuba(s)
    au, mirror, glass = (d[f"shape_{i}"]["bsdf"] for i in range(3))
    assert (au.class_name(), mirror.class_name(), glass.class_name()) == (
        "TwoSidedBRDF",
        "SmoothConductor",
        "RoughDielectric",
    )
    params = mi.traverse(au)
    assert params["brdf_0.alpha_u.value"] == pytest.approx(0.2) and params["brdf_0.alpha_v.value"] == pytest.approx(0.1)
    assert np.allclose(np.array(params["brdf_0.eta.value"]), s.materials["au"].eta, rtol=1e-6)
    assert np.allclose(np.array(params["brdf_0.k.value"]), s.materials["au"].k, rtol=1e-6)
    assert np.allclose(np.array(params["brdf_0.specular_reflectance.value"]), 0.9)
    assert mi.traverse(glass)["alpha.value"] == pytest.approx(0.1)
    render(s)


def test_unsupported_parts_are_named(tmp_path):
    (tmp_path / "t.ptab").write_bytes(b"")
    s = scene(
        tmp_path,
        materials={
            "paint": {"type": "carpaint", "base": {"type": "table", "file": "t.ptab"}},
            "l": {"type": "lambert"},
        },
        shapes=[
            {"type": "sphere", "material": "l"},
            {"type": "sphere", "material": "paint"},
        ],
    )
    with pytest.raises(MitsubaConversionError) as info:
        to_mitsuba(s)
    assert info.value.where == "materials.paint" and "carpaint" in info.value.problem
    s = scene(tmp_path, materials={"l": {"type": "lambert"}}, shapes=[{"type": "ball", "material": "l"}])
    with pytest.raises(MitsubaConversionError, match=r"shapes\[0\]: a ball shape needs its mesh arrays"):
        to_mitsuba(s)
    to_mitsuba(s, {0: icosphere()})  # with arrays it converts
    stretched = {"type": "sphere", "material": "l", "transform": {"scale": [1, 2, 1]}}
    s = scene(tmp_path, materials={"l": {"type": "lambert"}}, shapes=[stretched])
    with pytest.raises(MitsubaConversionError, match="non-uniform"):
        to_mitsuba(s)
    # a luminaire lit to its horizon (the street light, to 87.5 degrees) is no spot's cone
    street = os.path.join(ROOT, "materials", "luminaires", "streetlight.ies")
    s = scene(tmp_path, lights=[{"type": "luminaire", "file": street, "position": [0, 5, 0]}])
    with pytest.raises(MitsubaConversionError, match=r"lights\[0\]: a luminaire lit to 90 degrees"):
        to_mitsuba(s)


def test_carpaint_over_lambert_is_mitsubas_plastic():
    base = LambertMaterial((0.2, 0.3, 0.6), False)
    smooth = bsdf(CarpaintMaterial(base, Coat(1.5, 0.0, (1.0, 1.0, 1.0)), False))
    assert smooth["type"] == "plastic" and smooth["int_ior"] == 1.5 and smooth["nonlinear"] is False
    assert smooth["diffuse_reflectance"]["value"] == [0.2, 0.3, 0.6]
    rough = bsdf(CarpaintMaterial(base, Coat(1.4, 0.05, (1.0, 1.0, 1.0)), True))
    assert rough["type"] == "twosided" and rough["bsdf"]["type"] == "roughplastic"
    assert rough["bsdf"]["alpha"] == 0.05 and rough["bsdf"]["distribution"] == "ggx"
    with pytest.raises(MitsubaConversionError, match="thickness_tint"):
        bsdf(CarpaintMaterial(base, Coat(1.5, 0.0, (0.9, 1.0, 1.0)), False))


def _asymmetric_ies(path) -> str:
    """A type C table of no symmetry (brightest towards C = 34 degrees), dark past 70 degrees
    from the nadir: a mirrored or turned texture shows."""
    h = np.arange(0.0, 361.0, 30.0)
    v = np.arange(0.0, 91.0, 10.0)
    by_plane = 300 + 150 * np.cos(np.radians(h)) + 100 * np.sin(np.radians(h))
    candela = by_plane[:, None] * np.cos(np.radians(v))[None, :] ** 2
    candela[:, v >= 70] = 0.0
    path.write_text(format_ies(h, v, candela))
    return str(path)


@pytest.mark.parametrize(
    "file, aim, rotation",
    [("downlight.ies", [0.0, -1.0, 0.0], 0.0), ("asymmetric", [0.3, -1.0, 0.2], 40.0)],
)
def test_lambert_plane_under_a_luminaire(tmp_path, file, aim, rotation):
    """A luminaire is Mitsuba's spot projecting its candela table: a Lambert floor's radiance is
    albedo / pi * I(direction) cos / d^2 with I from the table, orientation and TILT included."""
    path = (
        _asymmetric_ies(tmp_path / "a.ies")
        if file == "asymmetric"
        else os.path.join(ROOT, "materials", "luminaires", file)
    )
    position = np.array([0.3, 2.0, -0.2])
    s = scene(
        tmp_path,
        camera={"position": [0, 5, 3], "look_at": [0, 0, 0], "fov": 60, "width": 32, "height": 24},
        render={"spp": 256, "integrator": "direct"},
        materials={"grey": {"type": "lambert", "albedo": 0.5}},
        shapes=[{"type": "plane", "material": "grey", "size": [40, 40]}],
        lights=[{"type": "luminaire", "file": path, "position": position.tolist(), "aim": aim, "rotation": rotation}],
    )
    image = render(s)
    points, valid = _plane_hits(s, 8)
    assert valid.all()
    lux = floor_illuminance(path, position, aim, rotation, points)
    rgb = np.asarray(rgb_per_candela(load_luminaire(path), aim, 1.0, (1.0, 1.0, 1.0)))
    expected = (0.5 / math.pi * lux[..., None] * rgb).mean(axis=2)
    lit = expected[..., 1] > 0.05 * expected[..., 1].max()
    assert lit.sum() > 100
    relative = np.abs(image[lit] / expected[lit] - 1)
    # pixels across the cut-off's edge are partly lit: the median and the mean say the texture is right
    assert np.median(relative) < 0.01 and relative.mean() < 0.03
    assert abs(image.sum() / expected.sum() - 1) < 0.01


def test_fit_material_is_the_exported_mitsuba_bsdf(tmp_path):
    """A fit.json material converts as `patina export --to mitsuba` writes it, and Mitsuba
    evaluates it as Patina evaluates the fit (Mitsuba's eval carries cos(theta_o))."""
    from export_helpers import GGX_FIT, write_json
    from patina.fitting import read_fit

    fit = write_json(tmp_path / "fit.json", GGX_FIT)
    s = scene(
        tmp_path, materials={"paint": {"type": "fit", "file": fit}}, shapes=[{"type": "sphere", "material": "paint"}]
    )
    converted = mi.load_dict(bsdf(s.materials["paint"]))
    wi, wo = np.array([0.3, 0.1, 0.95]), np.array([-0.4, 0.2, 0.89])
    wi, wo = wi / np.linalg.norm(wi), wo / np.linalg.norm(wo)
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(*wi)
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    value = np.array(converted.eval(mi.BSDFContext(), si, mi.Vector3f(*wo))) / wo[2]
    np.testing.assert_allclose(value, read_fit(fit).eval(wi[None], wo[None])[0], rtol=0.01)
    with pytest.raises(MitsubaConversionError, match="fit"):
        bsdf(scene(tmp_path, materials={"m": {"type": "fit", "file": fit, "scale": 2}}).materials["m"], "materials.m")
