"""Scene files (JSON, docs/scene.md) parsed into the frozen dataclasses of `patina.scene.types`.

    scene = load_scene("materials/scenes/preview-ball.json")
    scene = with_overrides(scene, spp=16)           # what the command line changes
    json.dumps(scene_to_json(scene))                # canonical form, for EXR metadata

Every default is filled here and every path resolved against the scene file's folder,
so nothing downstream re-reads the format's rules. Anything wrong — JSON syntax, an
unknown or missing key, a wrong type, an impossible value, a missing file, an undefined
material — is a `FormatError(path, key path, problem)` such as
`materials.paint.coat.eta: must be >= 1, got 0.5`; never another exception.

Light kinds are a table (`LIGHT_KINDS`, name -> parser): a new kind is a dataclass in
scene_types, a parser here and a line in the table; `scene_to_json` needs nothing new.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
from collections.abc import Callable
from typing import Any

import numpy as np

from patina.colour_constants import luminance, photometric_to_rgb
from patina.errors import FormatError
from patina.geometry.mesh import MESH_FORMATS
from patina.native import _core
from patina.scene.json_reader import Ctx, Obj, array, boolean, choice, integer, key_path, number, object_pairs, rgb
from patina.scene.json_reader import existing_file as _file
from patina.scene.json_reader import string as _string
from patina.scene.json_reader import vector as _vector
from patina.scene.metals import METALS
from patina.scene.types import (
    BallShape,
    CacheParams,
    Camera,
    CarpaintMaterial,
    Coat,
    ConductorMaterial,
    ConstantEnvironment,
    DielectricMaterial,
    DiskLight,
    Environment,
    FitMaterial,
    LambertMaterial,
    Light,
    LuminaireLight,
    MapEnvironment,
    Material,
    MeshLight,
    MeshShape,
    PanelShape,
    PlaneShape,
    PointLight,
    QuadLight,
    Render,
    RglMaterial,
    Scene,
    Shape,
    SphereLight,
    SphereShape,
    SpotLight,
    SunLight,
    TableMaterial,
)
from patina.table.formats.loading import SIDES

VERSION = 1
MAX_FILE_BYTES = 16 << 20  # a scene is a few kB; anything this large is not one
MAX_IMAGE_SIDE = 16384
# the renderer's ranges of render.spp, render.max_depth, render.aa_threshold and --threads: its
# one table (render/render_options.h), read through the binding
RENDER_RANGES = {key: (lo, hi) for key, _integer, lo, hi in _core.render_option_ranges()}
MAX_SPP = int(RENDER_RANGES["spp"][1])
MAX_DEPTH = int(RENDER_RANGES["max_depth"][1])
AA_THRESHOLD_RANGE = RENDER_RANGES["aa_threshold"]
MAX_SEED = (1 << 63) - 1
# Ranges that keep a render inside the renderer's 32-bit floats (docs/scene.md, "Limits"):
# radiance times BRDF times the sums of up to MAX_SPP samples must stay far below 3.4e38.
MAX_EMISSION = 1e15  # W/sr, W/m^2/sr or W/m^2 per channel (the sun's radiance is ~2e7)
MAX_REFLECTANCE_SCALE = 1e6  # a material's scale times tint
MAX_BRDF = 1e8  # a table's or fit's largest value times scale and tint (a mirror-like peak ~1e4)
MAX_OPTICAL_CONSTANT = 1000.0  # eta, k (real materials: below ~100)
MIN_LENGTH, MAX_LENGTH = 1e-6, 1e9  # metres: sizes, radii, |coordinates|
MIN_SUN_DIAMETER = 1e-3  # degrees; its radiance grows as 1 / diameter^2
OVERFLOWS = "larger values overflow the renderer's 32-bit floats"
OUT_OF_RANGE = "smaller ones vanish and larger ones overflow in the renderer's 32-bit floats"
TABLE_SUFFIXES = (".ptab", ".binary", ".astm", ".csv", ".txt", ".brdf", ".dat", ".bsdf", ".mbsdf", ".bin", ".xml")
MESH_SUFFIXES = tuple(f".{s}" for s in MESH_FORMATS)
ENV_SUFFIXES = (".exr", ".hdr")
NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_-]{0,63}")
_TOP_KEYS = ("version", "camera", "render", "materials", "shapes", "lights", "environment")


# --- small readers --------------------------------------------------------------------------


def vec3(ctx: Ctx, where: str, value: Any) -> tuple[float, float, float]:
    x, y, z = _vector(ctx, where, value, 3, lo=-MAX_LENGTH, hi=MAX_LENGTH)
    return (x, y, z)


def length(ctx: Ctx, where: str, value: Any) -> float:
    """A size in metres, in [MIN_LENGTH, MAX_LENGTH]: smaller ones vanish in the renderer's
    32-bit floats (a sphere of radius 1e-300 has no triangles), larger ones overflow them."""
    return number(ctx, where, value, lo=MIN_LENGTH, hi=MAX_LENGTH)


def _positive_pair(ctx: Ctx, where: str, value: Any) -> tuple[float, float]:
    a, b = _vector(ctx, where, value, 2, lo=MIN_LENGTH, hi=MAX_LENGTH)
    return (a, b)


def _limited(ctx: Ctx, where: str, values: tuple[float, ...], limit: float, unit: str) -> None:
    if max(values) > limit:
        ctx.fail(where, f"{max(values):g} {unit} is more than {limit:g}: {OVERFLOWS}")


def emission_rgb(ctx: Ctx, where: str, value: Any) -> tuple[float, float, float]:
    """A radiometric RGB emission (>= 0) within MAX_EMISSION."""
    c = rgb(ctx, where, value, lo=0.0)
    _limited(ctx, where, c, MAX_EMISSION, "per channel")
    return c


def _optical(ctx: Ctx, where: str, value: Any, **limits: Any) -> tuple[float, float, float]:
    return rgb(ctx, where, value, hi=MAX_OPTICAL_CONSTANT, **limits)


def _tint(ctx: Ctx, where: str, value: Any) -> tuple[float, float, float]:
    c = rgb(ctx, where, value, lo=0.0)
    _limited(ctx, where, c, MAX_REFLECTANCE_SCALE, "per channel")
    return c


def _roughness_pair(ctx: Ctx, where: str, value: Any) -> tuple[float, float]:
    """One GGX alpha (isotropic) or [alpha_x, alpha_y], each in [0, 1]."""
    if isinstance(value, list):
        ax, ay = _vector(ctx, where, value, 2, lo=0.0, hi=1.0)
        return (ax, ay)
    a = number(ctx, where, value, lo=0.0, hi=1.0)
    return (a, a)


def _unit_or_fail(ctx: Ctx, where: str, v: np.ndarray, problem: str) -> np.ndarray:
    with np.errstate(all="ignore"):
        n = float(np.linalg.norm(v))
        u = v / n if n > 0 else v
    if not (math.isfinite(n) and n > 0 and np.isfinite(u).all() and abs(float(np.linalg.norm(u)) - 1) < 1e-9):
        ctx.fail(where, problem)
    return u


# --- camera and render ----------------------------------------------------------------------


def _camera(o: Obj) -> Camera:
    kind = o.read("type", choice, "pinhole", options=("pinhole", "thinlens"))
    keys = ["type", "position", "look_at", "up", "fov", "width", "height"]
    o.allow([*keys, "aperture_radius", "focus_distance"] if kind == "thinlens" else keys, f"a {kind} camera")
    position = o.read("position", vec3)
    look_at = o.read("look_at", vec3)
    up = o.read("up", vec3, (0.0, 1.0, 0.0))
    with np.errstate(all="ignore"):
        offset = np.subtract(look_at, position)
    forward = _unit_or_fail(o.ctx, o.at("look_at"), offset, "must differ from camera.position (at a finite distance)")
    up_unit = _unit_or_fail(o.ctx, o.at("up"), np.asarray(up), "must be a non-zero vector")
    if np.linalg.norm(np.cross(forward, up_unit)) < 1e-6:
        o.ctx.fail(o.at("up"), "is parallel to the view direction (look_at - position)")
    distance = float(np.linalg.norm(offset))
    return Camera(
        type=kind,
        position=position,
        look_at=look_at,
        up=up,
        fov=o.read("fov", number, 30.0, lo=0.0, hi=180.0, lo_open=True, hi_open=True),
        width=o.read("width", integer, 640, lo=1, hi=MAX_IMAGE_SIDE),
        height=o.read("height", integer, 480, lo=1, hi=MAX_IMAGE_SIDE),
        aperture_radius=o.read("aperture_radius", number, 0.0, lo=0.0, hi=MAX_LENGTH),
        focus_distance=o.read("focus_distance", length, distance),
    )


AA_SAMPLERS = ("uniform", "adaptive")  # render.aa, --aa (docs/antialiasing.md)
AA_THRESHOLD = 0.15  # the adaptive sampler's contrast threshold; contrasts are in [0, 1]
SAMPLERS = ("sobol", "independent")  # render.sampler, --sampler: the paths' numbers (docs/render.md)


INTEGRATORS = ("direct", "path", "cache", "cache-guided")  # render.integrator, --integrator
# the radiance cache's parameters (docs/radiance-cache.md): render.cache.<key>, --cache-<key>;
# their ranges are the C++ side's one table (render/cache/cache_settings.h), read through the binding
_CACHE_SETTINGS = _core.cache_setting_ranges()
CACHE_RANGES: dict[str, tuple[float, float]] = {
    key: (int(lo), int(hi)) if integer else (lo, hi) for key, integer, lo, hi in _CACHE_SETTINGS
}
CACHE_INTEGER_KEYS = tuple(key for key, integer, _lo, _hi in _CACHE_SETTINGS if integer)


def _cache_params(o: Obj) -> CacheParams:
    o.allow(tuple(CACHE_RANGES), "render.cache")
    d = CacheParams()
    values = {}
    for key, (lo, hi) in CACHE_RANGES.items():
        if key in CACHE_INTEGER_KEYS:
            values[key] = o.read(key, integer, getattr(d, key), lo=int(lo), hi=int(hi))
        else:
            values[key] = o.read(key, number, getattr(d, key), lo=lo, hi=hi)
    return CacheParams(**values)


def _render(o: Obj) -> Render:
    keys = ("spp", "integrator", "max_depth", "seed", "aa", "aa_threshold", "indirect_illuminance", "sampler", "cache")
    o.allow(keys, "render")
    return Render(
        spp=o.read("spp", integer, 64, lo=1, hi=MAX_SPP),
        integrator=o.read("integrator", choice, "direct", options=INTEGRATORS),
        max_depth=o.read("max_depth", integer, 8, lo=1, hi=MAX_DEPTH),
        seed=o.read("seed", integer, 0, lo=0, hi=MAX_SEED),
        aa=o.read("aa", choice, "uniform", options=AA_SAMPLERS),
        aa_threshold=o.read("aa_threshold", number, AA_THRESHOLD, lo=AA_THRESHOLD_RANGE[0], hi=AA_THRESHOLD_RANGE[1]),
        indirect_illuminance=o.read("indirect_illuminance", boolean, False),
        sampler=o.read("sampler", choice, "sobol", options=SAMPLERS),
        cache=_cache_params(o.obj("cache", {})),
    )


# --- materials ------------------------------------------------------------------------------

MATERIAL_KINDS = ("table", "rgl", "fit", "lambert", "conductor", "dielectric", "carpaint")
BASE_KINDS = ("table", "rgl", "fit", "lambert")
RGL_SAMPLING = ("file", "cosine")  # the file's own warps, or the cosine (to compare)


def _material(o: Obj, kinds: tuple[str, ...] = MATERIAL_KINDS, outer_two_sided: bool | None = None) -> Material:
    """A material object; a carpaint's base (`outer_two_sided` given) is a base kind without two_sided."""
    kind = o.read("type", choice, options=kinds)
    keys = {
        "table": ("file", "scale", "tint", "two_sided"),
        "rgl": ("file", "scale", "tint", "two_sided", "sampling"),
        "fit": ("file", "scale", "tint", "two_sided"),
        "lambert": ("albedo", "two_sided"),
        "conductor": ("roughness", "metal", "eta", "k", "tint", "two_sided"),
        "dielectric": ("roughness", "eta"),
        "carpaint": ("base", "coat", "two_sided"),
    }[kind]
    if outer_two_sided is not None:
        if o.has("two_sided"):
            o.ctx.fail(o.at("two_sided"), "set two_sided on the carpaint material, not on its base")
        keys = tuple(k for k in keys if k != "two_sided")
    o.allow(("type", *keys), f"a {kind} material")
    two_sided = outer_two_sided if outer_two_sided is not None else o.read("two_sided", boolean, False)
    if kind in ("table", "rgl", "fit"):
        return _measured(o, kind, two_sided)
    if kind == "lambert":
        return LambertMaterial(albedo=o.read("albedo", rgb, (0.5, 0.5, 0.5), lo=0.0, hi=1.0), two_sided=two_sided)
    if kind == "conductor":
        return _conductor(o, two_sided)
    if kind == "dielectric":
        return DielectricMaterial(
            roughness=o.read("roughness", number, 0.0, lo=0.0, hi=1.0),
            eta=o.read("eta", number, 1.5, lo=1.0, hi=MAX_OPTICAL_CONSTANT),
        )
    base = _material(o.obj("base"), BASE_KINDS, two_sided)
    coat = o.obj("coat", {})
    coat.allow(("eta", "roughness", "thickness_tint"), "a clear coat")
    return CarpaintMaterial(
        base=base,  # type: ignore[arg-type]
        coat=Coat(
            eta=coat.read("eta", number, 1.5, lo=1.0, hi=MAX_OPTICAL_CONSTANT),
            roughness=coat.read("roughness", number, 0.0, lo=0.0, hi=1.0),
            thickness_tint=coat.read("thickness_tint", rgb, (1.0, 1.0, 1.0), lo=0.0, hi=1.0),
        ),
        two_sided=two_sided,
    )


def _measured(o: Obj, kind: str, two_sided: bool) -> TableMaterial | RglMaterial | FitMaterial:
    """A table, an RGL file or a fit: its file, scale and tint (an RGL file also its sampling)."""
    scale = o.read("scale", number, 1.0, lo=0.0)
    tint = o.read("tint", _tint, (1.0, 1.0, 1.0))
    _limited(o.ctx, o.at("scale"), tuple(scale * t for t in tint), MAX_REFLECTANCE_SCALE, "(scale x tint)")
    if kind == "table":
        file = o.read("file", _table_file)
    else:
        file = o.read("file", _file, suffixes=(".bsdf",) if kind == "rgl" else (".json",))
    if kind == "rgl":
        sampling = o.read("sampling", choice, "file", options=RGL_SAMPLING)
        return RglMaterial(file=file, scale=scale, tint=tint, two_sided=two_sided, sampling=sampling)
    cls = TableMaterial if kind == "table" else FitMaterial
    return cls(file=file, scale=scale, tint=tint, two_sided=two_sided)


def _table_file(ctx: Ctx, where: str, value: Any) -> str:
    """A table file, which may name a BSDF XML document's side as on the command line
    (`window.xml#back`): the file is checked without the side, which stays on the path."""
    name = _string(ctx, where, value)
    base, mark, side = name.rpartition("#")
    if mark and base.lower().endswith(".xml"):
        if side not in SIDES:
            ctx.fail(where, f"'#{side}': expected #front or #back (the side of a BSDF XML document)")
        return f"{_file(ctx, where, base, suffixes=('.xml',))}#{side}"
    return _file(ctx, where, name, suffixes=TABLE_SUFFIXES)


def _conductor(o: Obj, two_sided: bool) -> ConductorMaterial:
    metal = o.read("metal", choice, None, options=tuple(METALS))
    if metal is not None:
        for key in ("eta", "k"):
            if o.has(key):
                o.ctx.fail(o.at(key), "give either 'metal' or both 'eta' and 'k', not both")
        eta, k = METALS[metal]
    elif not (o.has("eta") or o.has("k")):
        o.ctx.fail(o.at("metal"), f"missing: give 'metal' ({', '.join(METALS)}) or both 'eta' and 'k'")
    else:
        eta = o.read("eta", _optical, lo=0.0, lo_open=True)
        k = o.read("k", _optical, lo=0.0)
    return ConductorMaterial(
        roughness=o.read("roughness", _roughness_pair, (0.1, 0.1)),
        eta=eta,
        k=k,
        tint=o.read("tint", _tint, (1.0, 1.0, 1.0)),
        metal=metal,
        two_sided=two_sided,
    )


def _materials(o: Obj) -> dict[str, Material]:
    out: dict[str, Material] = {}
    for name in o.value:
        if not NAME.fullmatch(name):
            o.ctx.fail(o.at(name), "a material name is 1-64 letters, digits, '_' or '-' (not starting with '-')")
        out[name] = _material(o.obj(name))
    return out


# --- transforms -----------------------------------------------------------------------------


def rotation(axis: np.ndarray, degrees: float) -> np.ndarray:
    """4x4 right-handed rotation about a unit axis (counter-clockwise looking down the axis)."""
    x, y, z = axis
    a = math.radians(degrees)
    c, s, t = math.cos(a), math.sin(a), 1 - math.cos(a)
    m = np.eye(4)
    m[:3, :3] = [
        [t * x * x + c, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, t * y * y + c, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, t * z * z + c],
    ]
    return m


def _one_rotation(ctx: Ctx, where: str, value: Any) -> np.ndarray:
    pair = array(ctx, where, value, 2)
    axis = np.asarray(vec3(ctx, key_path(where, 0), pair[0]))
    unit = _unit_or_fail(ctx, key_path(where, 0), axis, "the rotation axis must be a non-zero vector")
    return rotation(unit, number(ctx, key_path(where, 1), pair[1]))


def _rotations(ctx: Ctx, where: str, value: Any) -> np.ndarray:
    """[[ax, ay, az], degrees], or a list of those applied first to last."""
    items = array(ctx, where, value)
    if len(items) == 2 and not isinstance(items[1], list):
        return _one_rotation(ctx, where, items)
    m = np.eye(4)
    for i, item in enumerate(items):
        m = _one_rotation(ctx, key_path(where, i), item) @ m
    return m


def _matrix(ctx: Ctx, where: str, value: Any) -> np.ndarray:
    rows = array(ctx, where, value, 4)
    m = np.array([_vector(ctx, key_path(where, i), row, 4) for i, row in enumerate(rows)])
    if not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        ctx.fail(key_path(where, 3), "the last row of an affine transform must be [0, 0, 0, 1]")
    return m


def _scale(ctx: Ctx, where: str, value: Any) -> tuple[float, float, float]:
    """One factor or [sx, sy, sz], none zero (negative mirrors)."""
    if isinstance(value, list):
        sx, sy, sz = _vector(ctx, where, value, 3)
    else:
        sx = sy = sz = number(ctx, where, value)
    if 0.0 in (sx, sy, sz):
        ctx.fail(where, "scale factors must be non-zero")
    if not all(MIN_LENGTH <= abs(f) <= MAX_LENGTH for f in (sx, sy, sz)):
        ctx.fail(where, f"scale factors must be {MIN_LENGTH:g} to {MAX_LENGTH:g} in size (or negative): {OUT_OF_RANGE}")
    return (sx, sy, sz)


def _transform(o: Obj) -> np.ndarray:
    if o.has("matrix"):
        o.allow(("matrix",), "a matrix transform (a matrix replaces translate, rotate and scale)")
        m = o.read("matrix", _matrix)
    else:
        o.allow(("translate", "rotate", "scale"), "a transform")
        factors = o.read("scale", _scale, (1.0, 1.0, 1.0))
        t = np.eye(4)
        t[:3, 3] = o.read("translate", vec3, (0.0, 0.0, 0.0))
        with np.errstate(all="ignore"):
            m = t @ o.read("rotate", _rotations, np.eye(4)) @ np.diag([*factors, 1.0])
    with np.errstate(all="ignore"):
        det = np.linalg.det(m[:3, :3]) if np.isfinite(m).all() else math.nan
        size = np.abs(m[:3, :3]).max()
    if not (math.isfinite(det) and abs(det) > 1e-12 * size**3):
        o.ctx.fail(o.where, "the transform is singular or not finite")
    m.setflags(write=False)
    return m


# --- shapes ---------------------------------------------------------------------------------

SHAPE_KINDS = ("sphere", "plane", "ball", "panel", "mesh")


def _shape(o: Obj, materials: dict[str, Material]) -> Shape:
    kind = o.read("type", choice, options=SHAPE_KINDS)
    params = {"sphere": ("radius", "analytic"), "plane": ("size",), "ball": (), "panel": ("size",), "mesh": ("file",)}[
        kind
    ]
    o.allow(("type", "material", "transform", *params), f"a {kind} shape")
    material = o.read("material", _string)
    if material not in materials:
        known = ", ".join(materials) or "none are defined"
        o.ctx.fail(o.at("material"), f"undefined material '{material[:40]}' (materials: {known})")
    transform = _transform(o.obj("transform")) if o.has("transform") else _identity()
    if kind == "sphere":
        analytic = o.read("analytic", boolean, False)
        if analytic and similarity_scale(transform[:3, :3]) is None:
            o.ctx.fail(
                o.at("analytic"),
                "an analytic sphere takes only translate, rotate and a uniform positive scale "
                "(its transform is not a similarity: a non-uniform scale, a mirror or a shear needs the triangles)",
            )
        return SphereShape(material, transform, o.read("radius", length, 1.0), analytic)
    if kind == "plane":
        return PlaneShape(material, transform, o.read("size", _positive_pair, (2.0, 2.0)))
    if kind == "ball":
        return BallShape(material, transform)
    if kind == "panel":
        return PanelShape(material, transform, o.read("size", _positive_pair, (2.0, 1.2)))
    return MeshShape(material, transform, o.read("file", _file, suffixes=MESH_SUFFIXES))


def similarity_scale(lin: np.ndarray) -> float | None:
    """The uniform scale s of a 3x3 matrix that is a rotation times s > 0 (L^T L = s^2 I within
    1e-9 s^2, det > 0), None for any other (a mirror, shear or non-uniform scale)."""
    gram = np.asarray(lin, np.float64).T @ np.asarray(lin, np.float64)
    s2 = float(np.trace(gram)) / 3
    if s2 > 0 and np.allclose(gram, s2 * np.eye(3), rtol=0, atol=1e-9 * s2) and np.linalg.det(lin) > 0:
        return math.sqrt(s2)
    return None


def _identity() -> np.ndarray:
    m = np.eye(4)
    m.setflags(write=False)
    return m


# --- lights and environment -----------------------------------------------------------------


def _color(o: Obj) -> tuple[float, float, float]:
    """The optional `color` of a photometric emission (white by default), of positive luminance."""
    color = o.read("color", rgb, (1.0, 1.0, 1.0), lo=0.0)
    if not float(luminance(np.asarray(color))) > 0:
        o.ctx.fail(o.at("color"), "the colour must have a positive luminance")
    return color


def _emission(o: Obj, radiometric: str, photometric: str, what: str) -> tuple[float, float, float]:
    """The radiometric RGB of `radiometric` (RGB or grey), or of `photometric` (a number in
    photometric units) with an optional `color`; exactly one of the two must be given."""
    given = [k for k in (radiometric, photometric) if o.has(k)]
    if len(given) != 1:
        o.ctx.fail(o.where, f"{what} needs exactly one of '{radiometric}' or '{photometric}'")
    if given[0] == radiometric:
        if o.has("color"):
            o.ctx.fail(o.at("color"), f"a colour goes with '{photometric}'; '{radiometric}' is already RGB")
        return o.read(radiometric, emission_rgb)
    # a value in candela, cd/m^2 or lux becomes radiometric RGB at 683 lm/W of luminance
    c = photometric_to_rgb(o.read(photometric, number, lo=0.0), _color(o))
    _limited(o.ctx, o.at(photometric), c, MAX_EMISSION, "W per channel (with its colour)")
    return c


def _unit_vec3(ctx: Ctx, where: str, value: Any) -> tuple[float, float, float]:
    v = np.asarray(vec3(ctx, where, value), np.float64)
    u = _unit_or_fail(ctx, where, v, "must be a non-zero direction")
    return (float(u[0]), float(u[1]), float(u[2]))


def _point_light(o: Obj) -> PointLight:
    o.allow(("type", "position", "intensity", "intensity_cd", "color"), "a point light")
    return PointLight(
        position=o.read("position", vec3), intensity=_emission(o, "intensity", "intensity_cd", "a point light")
    )


def _spot_light(o: Obj) -> SpotLight:
    keys = ("type", "position", "direction", "intensity", "intensity_cd", "color", "inner_angle", "outer_angle")
    o.allow(keys, "a spot light")
    outer = o.read("outer_angle", number, 30.0, lo=0.0, hi=180.0, lo_open=True)
    inner = o.read("inner_angle", number, 0.8 * outer, lo=0.0)
    if not inner < outer:
        o.ctx.fail(o.at("inner_angle"), f"must be smaller than outer_angle ({outer:g})")
    return SpotLight(
        position=o.read("position", vec3),
        direction=o.read("direction", _unit_vec3),
        intensity=_emission(o, "intensity", "intensity_cd", "a spot light"),
        inner_angle=inner,
        outer_angle=outer,
    )


def _disk_light(o: Obj) -> DiskLight:
    o.allow(("type", "center", "normal", "radius", "radiance", "luminance", "color", "two_sided"), "a disk light")
    return DiskLight(
        center=o.read("center", vec3),
        normal=o.read("normal", _unit_vec3),
        radius=o.read("radius", length),
        radiance=_emission(o, "radiance", "luminance", "a disk light"),
        two_sided=o.read("two_sided", boolean, False),
    )


def _sphere_light(o: Obj) -> SphereLight:
    o.allow(("type", "center", "radius", "radiance", "luminance", "color"), "a sphere light")
    return SphereLight(
        center=o.read("center", vec3),
        radius=o.read("radius", length),
        radiance=_emission(o, "radiance", "luminance", "a sphere light"),
    )


def _mesh_light(o: Obj) -> MeshLight:
    o.allow(("type", "file", "transform", "radiance", "luminance", "color", "two_sided"), "a mesh light")
    transform = _transform(o.obj("transform")) if o.has("transform") else _identity()
    return MeshLight(
        "",
        transform,
        o.read("file", _file, suffixes=MESH_SUFFIXES),
        _emission(o, "radiance", "luminance", "a mesh light"),
        o.read("two_sided", boolean, False),
    )


LUMINAIRE_SUFFIXES = (".ies", ".ldt")


def _luminaire_light(o: Obj) -> LuminaireLight:
    o.allow(("type", "file", "position", "aim", "rotation", "multiplier", "color"), "a luminaire")
    color = _color(o)
    return LuminaireLight(
        file=o.read("file", _file, suffixes=LUMINAIRE_SUFFIXES),
        position=o.read("position", vec3),
        aim=o.read("aim", _unit_vec3, (0.0, -1.0, 0.0)),
        rotation=o.read("rotation", number, 0.0),
        multiplier=o.read("multiplier", number, 1.0, lo=0.0, hi=MAX_EMISSION),
        color=color,
    )


def _sun_light(o: Obj) -> SunLight:
    o.allow(("type", "direction", "angular_diameter", "irradiance", "illuminance", "color"), "a sun")
    return SunLight(
        direction=o.read("direction", _unit_vec3),
        angular_diameter=o.read("angular_diameter", number, 0.53, lo=MIN_SUN_DIAMETER, hi=20.0),
        irradiance=_emission(o, "irradiance", "illuminance", "a sun"),
    )


def _quad_light(o: Obj) -> QuadLight:
    o.allow(("type", "center", "u", "v", "radiance", "luminance", "color", "two_sided"), "a quad light")
    u, v = o.read("u", vec3), o.read("v", vec3)
    for key, w in (("u", u), ("v", v)):
        _unit_or_fail(o.ctx, o.at(key), np.asarray(w), "a half-edge vector must be non-zero")
        if float(np.linalg.norm(w)) < MIN_LENGTH:
            o.ctx.fail(o.at(key), f"a half-edge vector must be at least {MIN_LENGTH:g} m long")
    with np.errstate(all="ignore"):
        n = np.cross(u, v)
        ok = np.isfinite(n).all() and np.linalg.norm(n) > 1e-9 * np.linalg.norm(u) * np.linalg.norm(v)
    if not ok:
        o.ctx.fail(o.at("v"), "u and v are parallel: the quad has no area")
    return QuadLight(
        center=o.read("center", vec3),
        u=u,
        v=v,
        radiance=_emission(o, "radiance", "luminance", "a quad light"),
        two_sided=o.read("two_sided", boolean, False),
    )


# name -> parser of a light object (the parser checks its own keys); add later kinds here
LIGHT_KINDS: dict[str, Callable[[Obj], Light]] = {
    "point": _point_light,
    "quad": _quad_light,
    "spot": _spot_light,
    "disk": _disk_light,
    "sphere": _sphere_light,
    "mesh": _mesh_light,
    "sun": _sun_light,
    "luminaire": _luminaire_light,
}


def _light(o: Obj) -> Light:
    return LIGHT_KINDS[o.read("type", choice, options=tuple(LIGHT_KINDS))](o)


def _environment(o: Obj) -> Environment:
    kind = o.read("type", choice, options=("map", "constant"))
    if kind == "constant":
        o.allow(("type", "radiance"), "a constant environment")
        return ConstantEnvironment(radiance=o.read("radiance", emission_rgb))
    o.allow(("type", "file", "rotation", "intensity"), "an environment map")
    return MapEnvironment(
        file=o.read("file", _file, suffixes=ENV_SUFFIXES),
        rotation=o.read("rotation", number, 0.0),
        intensity=o.read("intensity", number, 1.0, lo=0.0, hi=MAX_EMISSION),
    )


def _list(o: Obj, key: str, item: Callable[[Obj], Any]) -> tuple[Any, ...]:
    values = o.read(key, array, [])
    return tuple(item(Obj(o.ctx, key_path(o.at(key), i), v)) for i, v in enumerate(values))


# --- entry points ---------------------------------------------------------------------------


def parse_scene(obj: Any, path: str | os.PathLike[str]) -> Scene:
    """A decoded scene (JSON values) -> Scene; relative file names start from `path`'s folder."""
    shown = os.fspath(path)
    absolute = os.path.abspath(shown)
    ctx = Ctx(shown, os.path.dirname(absolute))
    top = Obj(ctx, "", obj, "a JSON object (a Patina scene)")
    top.allow(_TOP_KEYS, "a scene")
    version = top.read("version", integer)
    if version != VERSION:
        ctx.fail("version", f"unsupported scene version {version} (this Patina reads version {VERSION})")
    materials = _materials(top.obj("materials", {}))
    return Scene(
        path=absolute,
        camera=_camera(top.obj("camera")),
        render=_render(top.obj("render", {})),
        materials=materials,
        shapes=_list(top, "shapes", lambda o: _shape(o, materials)),
        lights=_list(top, "lights", _light),
        environment=_environment(top.obj("environment")) if top.has("environment") else None,
    )


def decode_json(data: bytes, path: str) -> Any:
    """UTF-8 JSON bytes -> Python values; syntax errors name the line and column."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise FormatError(path, f"byte {e.start}", "not UTF-8 text") from None
    try:
        return json.loads(text, object_pairs_hook=object_pairs)
    except json.JSONDecodeError as e:
        raise FormatError(path, f"line {e.lineno}, column {e.colno}", f"JSON syntax: {e.msg}") from None
    except RecursionError:
        raise FormatError(path, "", "JSON nested too deeply") from None
    except ValueError as e:  # e.g. an integer literal with thousands of digits
        raise FormatError(path, "", f"JSON value not readable: {e}") from None


def load_scene(path: str | os.PathLike[str]) -> Scene:
    """Reads and checks a scene file; every problem is a FormatError naming the key path."""
    shown = os.fspath(path)
    try:
        with open(shown, "rb") as f:
            data = f.read(MAX_FILE_BYTES + 1)
    except IsADirectoryError:
        raise FormatError(shown, "", "is a directory, not a scene file") from None
    except OSError as e:
        raise FormatError(shown, "", f"cannot open: {e.strerror}") from None
    if len(data) > MAX_FILE_BYTES:
        raise FormatError(shown, "", f"larger than {MAX_FILE_BYTES >> 20} MiB: not a scene file")
    return parse_scene(decode_json(data, shown), shown)


# --- command-line overrides ------------------------------------------------------------------


def with_overrides(
    scene: Scene,
    spp: int | None = None,
    integrator: str | None = None,
    seed: int | None = None,
    width: int | None = None,
    height: int | None = None,
    aa: str | None = None,
    aa_threshold: float | None = None,
    indirect_illuminance: bool | None = None,
    sampler: str | None = None,
    **cache: float | None,
) -> Scene:
    """The scene with command-line settings replacing the file's; bad values are FormatErrors
    naming the option (file "command line"). `cache`: cache_<key> for each render.cache key
    (cache_train_bounces=2, --cache-train-bounces); None leaves the file's."""
    ctx = Ctx("command line", os.getcwd())
    render, camera = scene.render, scene.camera
    if spp is not None:
        render = dataclasses.replace(render, spp=integer(ctx, "--spp", spp, lo=1, hi=MAX_SPP))
    if integrator is not None:
        render = dataclasses.replace(render, integrator=choice(ctx, "--integrator", integrator, INTEGRATORS))
    unknown = sorted(set(cache) - {f"cache_{key}" for key in CACHE_RANGES})
    if unknown:
        raise TypeError(f"with_overrides() got an unexpected keyword argument {unknown[0]!r}")
    params = render.cache
    for key in CACHE_RANGES:
        given = cache.get(f"cache_{key}")
        if given is not None:
            lo, hi = CACHE_RANGES[key]
            option = f"--cache-{key.replace('_', '-')}"
            if key in CACHE_INTEGER_KEYS:
                value = integer(ctx, option, given, lo=int(lo), hi=int(hi))
            else:
                value = number(ctx, option, given, lo=lo, hi=hi)
            params = dataclasses.replace(params, **{key: value})
    render = dataclasses.replace(render, cache=params)
    if seed is not None:
        render = dataclasses.replace(render, seed=integer(ctx, "--seed", seed, lo=0, hi=MAX_SEED))
    if aa is not None:
        render = dataclasses.replace(render, aa=choice(ctx, "--aa", aa, AA_SAMPLERS))
    if aa_threshold is not None:
        lo, hi = AA_THRESHOLD_RANGE
        render = dataclasses.replace(render, aa_threshold=number(ctx, "--aa-threshold", aa_threshold, lo=lo, hi=hi))
    if indirect_illuminance is not None:
        render = dataclasses.replace(render, indirect_illuminance=bool(indirect_illuminance))
    if sampler is not None:
        render = dataclasses.replace(render, sampler=choice(ctx, "--sampler", sampler, SAMPLERS))
    if width is not None:
        camera = dataclasses.replace(camera, width=integer(ctx, "--width", width, lo=1, hi=MAX_IMAGE_SIDE))
    if height is not None:
        camera = dataclasses.replace(camera, height=integer(ctx, "--height", height, lo=1, hi=MAX_IMAGE_SIDE))
    return dataclasses.replace(scene, render=render, camera=camera)


MAX_THREADS = int(RENDER_RANGES["threads"][1])  # worker threads; more than any machine's cores is a typo
MAX_EXPOSURE = 64.0  # stops either way: 2^64 brightens 1e-19 to 1, well past any real image


def check_run_options(
    threads: int | None = None, exposure: float | str | None = None, samples: int | None = None
) -> None:
    """The render commands' options that are not scene settings, checked before any work:
    FormatErrors naming the option (file "command line"). `exposure` may be "auto"."""
    ctx = Ctx("command line", os.getcwd())
    if threads is not None:
        integer(ctx, "--threads", threads, lo=0, hi=MAX_THREADS)
    if exposure is not None and exposure != "auto":
        number(ctx, "--exposure", float(exposure), lo=-MAX_EXPOSURE, hi=MAX_EXPOSURE)
    if samples is not None:
        integer(ctx, "--samples", samples, lo=1, hi=MAX_SPP)
