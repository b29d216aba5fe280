"""A parsed Patina scene as a Mitsuba 3 scene dictionary, for the cross-check renders.

    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    image = mi.render(mi.load_dict(to_mitsuba(scene, meshes)))

Mitsuba 3 (PyPI `mitsuba`, the `test` extra) is the independent reference Patina's
renders are compared against, so this converter must mean exactly what docs/scene.md
says: the pinhole camera is Mitsuba's `perspective` with `fov_axis: "y"` (the same ray
through every film position), the lat-long map is Mitsuba's `envmap` (the same
convention) turned by the rotation as its `to_world`, a quad light is a `rectangle` whose
`to_world` takes [-1, 1]^2 to center + s u + t v, with a black BSDF, and a type C luminaire
whose light ends before 85 degrees from its nadir is a `spot` projecting its candela table
(`luminaire_spot`: exact up to the texture's bilinear filter). Shapes are Mitsuba
meshes built from the arrays given for them (vertex normals included); spheres and
planes without arrays become Mitsuba's analytic `sphere` and `rectangle`. A fitted material
(without scale or tint) is what `patina export --to mitsuba` writes for its fit.json
(patina.export.mitsuba: exact for Lambert + GGX, a refit for other models). Materials
Mitsuba has no equivalent for (tabulated, car paint over a table or a fit) raise
`MitsubaConversionError` naming the material: a cross-check needs the same material on
both sides. A car paint over a Lambert base (without `thickness_tint`) becomes Mitsuba's
`plastic` (`roughplastic` with GGX under a rough coat): the same coat over the same
diffuse base, though the two renderers need not agree on the light that goes back and
forth between coat and base; the cache benchmark (bench/cache_mitsuba.py), which measures
each renderer against its own reference, uses it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from patina.export import prepare
from patina.export.mitsuba import to_mitsuba_dict
from patina.export.refit import RefitError
from patina.export.source import load_source
from patina.photometry.luminaire import load_luminaire
from patina.photometry.placement import luminaire_axes, rgb_per_candela
from patina.scene.reading import similarity_scale
from patina.scene.types import (
    Camera,
    CarpaintMaterial,
    ConductorMaterial,
    ConstantEnvironment,
    DielectricMaterial,
    FitMaterial,
    LambertMaterial,
    LuminaireLight,
    MapEnvironment,
    Material,
    PlaneShape,
    PointLight,
    QuadLight,
    Scene,
    SphereShape,
    rotation_y,
)

VARIANT = "scalar_rgb"
MeshArrays = Any  # (vertices (V, 3), indices (T, 3), normals (V, 3) or None), or an object with those attributes


class MitsubaConversionError(ValueError):
    """Part of the scene has no Mitsuba 3 equivalent here: `where` (a key path) and `problem`."""

    def __init__(self, where: str, problem: str) -> None:
        self.where = where
        self.problem = problem
        super().__init__(f"{where}: {problem}")


def _mi(variant: str) -> Any:
    import mitsuba as mi

    if mi.variant() != variant:
        mi.set_variant(variant)
    return mi


def _rgb(value: Any) -> dict[str, Any]:
    return {"type": "rgb", "value": [float(x) for x in value]}


def _matrix(mi: Any, m: np.ndarray) -> Any:
    return mi.ScalarTransform4f(np.asarray(m, np.float64).tolist())


# --- sensor and integrator ------------------------------------------------------------------


def _sensor(mi: Any, camera: Camera, spp: int, seed: int) -> dict[str, Any]:
    sensor: dict[str, Any] = {
        "type": "perspective" if camera.type == "pinhole" else "thinlens",
        "fov": camera.fov,
        "fov_axis": "y",
        "near_clip": 1e-4,
        "to_world": mi.ScalarTransform4f().look_at(
            origin=list(camera.position), target=list(camera.look_at), up=list(camera.up)
        ),
        "film": {
            "type": "hdrfilm",
            "width": camera.width,
            "height": camera.height,
            "rfilter": {"type": "box"},  # each sample counts in its own pixel only, as in Patina
            "pixel_format": "rgb",
            "component_format": "float32",
        },
        "sampler": {"type": "independent", "sample_count": spp, "seed": seed % (1 << 32)},
    }
    if camera.type == "thinlens":
        sensor["aperture_radius"] = camera.aperture_radius
        sensor["focus_distance"] = camera.focus_distance
    return sensor


def _integrator(scene: Scene) -> dict[str, Any]:
    # the radiance cache integrators (cache, cache-guided) converge to what the path tracer does
    if scene.render.integrator == "direct":
        return {"type": "direct"}
    return {"type": "path", "max_depth": scene.render.max_depth, "hide_emitters": False}


# --- materials ------------------------------------------------------------------------------


def _fit_bsdf(material: FitMaterial, where: str) -> dict[str, Any]:
    """A fit.json's material as `patina export --to mitsuba` writes it (refitted if need be)."""
    try:
        return to_mitsuba_dict(prepare(load_source(material.file), "mitsuba"))
    except (RefitError, ValueError) as e:  # FormatError is a ValueError
        raise MitsubaConversionError(where, f"its fit cannot be exported: {e}") from None


def bsdf(material: Material, where: str = "material") -> dict[str, Any]:
    """The Mitsuba BSDF dictionary of a lambert, conductor, dielectric or fit material."""
    if isinstance(material, FitMaterial) and material.scale == 1.0 and tuple(material.tint) == (1.0, 1.0, 1.0):
        out = _fit_bsdf(material, where)
    elif isinstance(material, LambertMaterial):
        out: dict[str, Any] = {"type": "diffuse", "reflectance": _rgb(material.albedo)}
    elif isinstance(material, ConductorMaterial):
        out = {"type": "conductor", "eta": _rgb(material.eta), "k": _rgb(material.k)}
        out["specular_reflectance"] = _rgb(material.tint)
        ax, ay = material.roughness
        if ax > 0 or ay > 0:
            out.update(type="roughconductor", distribution="ggx", alpha_u=ax, alpha_v=ay)
    elif isinstance(material, CarpaintMaterial) and isinstance(material.base, LambertMaterial):
        coat = material.coat
        if tuple(coat.thickness_tint) != (1.0, 1.0, 1.0):
            raise MitsubaConversionError(where, "a car paint's thickness_tint has no Mitsuba 3 equivalent here")
        out = {"type": "plastic", "diffuse_reflectance": _rgb(material.base.albedo), "int_ior": coat.eta}
        out.update(ext_ior=1.0, nonlinear=False)
        if coat.roughness > 0:
            out.update(type="roughplastic", distribution="ggx", alpha=coat.roughness)
    elif isinstance(material, DielectricMaterial):
        out = {"type": "dielectric", "int_ior": material.eta, "ext_ior": 1.0}
        if material.roughness > 0:
            out.update(type="roughdielectric", distribution="ggx", alpha=material.roughness)
        return out  # a dielectric interface is two-sided by nature
    else:
        raise MitsubaConversionError(
            where,
            f"a {material.type} material has no Mitsuba 3 equivalent here (supported: lambert, conductor, "
            "dielectric, carpaint over lambert, fit without scale or tint)",
        )
    if material.two_sided:
        return {"type": "twosided", "bsdf": out}
    return out


# --- shapes ---------------------------------------------------------------------------------


def _arrays(mesh: MeshArrays) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    if hasattr(mesh, "vertices"):
        vertices, indices, normals = mesh.vertices, mesh.indices, getattr(mesh, "normals", None)
    else:
        vertices, indices, normals = mesh
    v = np.asarray(vertices, np.float64).reshape(-1, 3)
    i = np.asarray(indices, np.int64).reshape(-1, 3)
    n = None if normals is None else np.asarray(normals, np.float64).reshape(-1, 3)
    if len(v) == 0 or len(i) == 0 or i.min() < 0 or i.max() >= len(v) or (n is not None and n.shape != v.shape):
        raise ValueError("mesh arrays: need vertices (V, 3), indices (T, 3) in [0, V) and normals (V, 3) or None")
    return v, i, n


def mitsuba_mesh(mi: Any, name: str, mesh: MeshArrays, transform: np.ndarray, bsdf_object: Any) -> Any:
    """A mi.Mesh of the arrays moved to world space (normals by the inverse transpose; a mirroring
    transform reverses the winding so faces stay counter-clockwise seen from outside)."""
    v, i, n = _arrays(mesh)
    linear = transform[:3, :3]
    world = v @ linear.T + transform[:3, 3]
    if np.linalg.det(linear) < 0:
        i = i[:, ::-1]
    props = mi.Properties()
    props["bsdf"] = bsdf_object
    out = mi.Mesh(name, len(world), len(i), props=props, has_vertex_normals=n is not None)
    params = mi.traverse(out)
    params["vertex_positions"] = world.astype(np.float32).ravel()
    params["faces"] = i.astype(np.uint32).ravel()
    if n is not None:
        normals = n @ np.linalg.inv(linear)
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-30)
        params["vertex_normals"] = normals.astype(np.float32).ravel()
    params.update()
    return out


PLANE_TO_RECTANGLE = np.array([[0.5, 0, 0, 0], [0, 0, 1, 0], [0, -0.5, 0, 0], [0, 0, 0, 1]])  # times diag(w, d)


def _analytic_shape(mi: Any, shape: Any, where: str, bsdf_object: Any) -> dict[str, Any]:
    m = shape.transform
    if isinstance(shape, SphereShape):
        s = similarity_scale(m[:3, :3])
        if s is None:
            raise MitsubaConversionError(where, "a sphere under a non-uniform scale or mirror needs a mesh")
        return {"type": "sphere", "center": m[:3, 3].tolist(), "radius": shape.radius * s, "bsdf": bsdf_object}
    if isinstance(shape, PlaneShape):
        # Mitsuba's rectangle spans [-1, 1]^2 in xy with normal +z; ours spans the size in xz with normal +y
        w, d = shape.size
        local = PLANE_TO_RECTANGLE @ np.diag([w, d, 1.0, 1.0])
        return {"type": "rectangle", "to_world": _matrix(mi, m @ local), "bsdf": bsdf_object}
    raise MitsubaConversionError(where, f"a {shape.type} shape needs its mesh arrays (meshes[index])")


# --- lights and environment -----------------------------------------------------------------


def quad_to_world(light: QuadLight, flip: bool = False) -> np.ndarray:
    """The matrix taking Mitsuba's rectangle ([-1, 1]^2 in xy, normal +z) onto the quad; `flip`
    swaps u and v so the normal (and the emitting side) is reversed."""
    u, v = np.asarray(light.u, np.float64), np.asarray(light.v, np.float64)
    if flip:
        u, v = v, u
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = u, v, np.cross(u, v) / np.linalg.norm(np.cross(u, v)), light.center
    return m


# A luminaire becomes Mitsuba's `spot` with its candela table as the projected `texture`: the
# spot projects a texture over the plane z = 1 of its frame, |x|, |y| <= tan(cutoff_angle), so a
# type C table whose light ends before 90 degrees from the nadir is that texture exactly, up to
# the texels' bilinear filter (LUMINAIRE_TEXELS a side). Type B tables and light at 90 degrees or more
# from the nadir have no such equivalent.
LUMINAIRE_TEXELS = 1024
LUMINAIRE_MAX_CUTOFF_DEG = 85.0


def luminaire_spot(mi: Any, light: LuminaireLight, where: str) -> dict[str, Any]:
    """Mitsuba's `spot` for a type C luminaire: the cone to the first gamma past the table's last
    lit angle, each texel the light's RGB intensity towards it (W/sr, TILT and colour included)."""
    lum = load_luminaire(light.file)
    kind, _, v, candela = lum.grid()
    if kind != "C":
        raise MitsubaConversionError(where, "a type B luminaire has no Mitsuba 3 equivalent here")
    lit = np.nonzero(np.asarray(candela).max(axis=0) > 0)[0]
    cutoff = float(v[min(lit[-1] + 1, len(v) - 1)]) if len(lit) else math.radians(1.0)
    if math.degrees(cutoff) > LUMINAIRE_MAX_CUTOFF_DEG:
        problem = f"a luminaire lit to {math.degrees(cutoff):g} degrees from its nadir has no Mitsuba 3 equivalent here"
        raise MitsubaConversionError(where, problem + f" (a spot's cone ends before {LUMINAIRE_MAX_CUTOFF_DEG:g})")
    x, y, z = luminaire_axes(light.aim, light.rotation, kind)
    # the spot's frame: +z the nadir (-z of the luminaire), x the luminaire's x, y = z x x
    frame = np.eye(4)
    frame[:3, 0], frame[:3, 1], frame[:3, 2], frame[:3, 3] = x, -y, -z, light.position
    # texel (row j, column i) at u = (i + 0.5) / n, v = (j + 0.5) / n: the direction
    # ((2u - 1) tan, (2v - 1) tan, 1) of the spot's frame, (x, -y, -z) of the luminaire's
    n = LUMINAIRE_TEXELS
    t = (2 * (np.arange(n) + 0.5) / n - 1) * math.tan(cutoff)
    sx, sy = np.meshgrid(t, t)
    local = np.stack([sx, -sy, -np.ones_like(sx)], -1)
    local /= np.linalg.norm(local, axis=-1, keepdims=True)
    cd = np.asarray(lum.intensity_at(local.reshape(-1, 3)), np.float64).reshape(n, n)
    rgb = np.asarray(rgb_per_candela(lum, light.aim, light.multiplier, light.color), np.float64)
    texture = np.ascontiguousarray(cd[..., None] * rgb, np.float32)
    angle = math.degrees(cutoff)
    return {
        "type": "spot",
        "to_world": _matrix(mi, frame),
        "cutoff_angle": angle,
        "beam_width": angle - 1e-3,  # no falloff of its own (the table is the falloff), but a nonzero width
        "intensity": 1.0,
        "texture": {"type": "bitmap", "bitmap": mi.Bitmap(texture), "raw": True, "filter_type": "bilinear"},
    }


def _lights(mi: Any, scene: Scene) -> dict[str, Any]:
    out: dict[str, Any] = {}
    black = {"type": "diffuse", "reflectance": _rgb((0.0, 0.0, 0.0))}
    for index, light in enumerate(scene.lights):
        where = f"lights[{index}]"
        if isinstance(light, PointLight):
            out[f"light_{index}"] = {
                "type": "point",
                "position": list(light.position),
                "intensity": _rgb(light.intensity),
            }
        elif isinstance(light, QuadLight):
            for side in (False, True) if light.two_sided else (False,):
                out[f"light_{index}{'_back' if side else ''}"] = {
                    "type": "rectangle",
                    "to_world": _matrix(mi, quad_to_world(light, side)),
                    "bsdf": black,
                    "emitter": {"type": "area", "radiance": _rgb(light.radiance)},
                }
        elif isinstance(light, LuminaireLight):
            out[f"light_{index}"] = luminaire_spot(mi, light, where)
        else:
            raise MitsubaConversionError(where, f"a {light.type} light has no Mitsuba 3 equivalent here")
    env = scene.environment
    if isinstance(env, ConstantEnvironment):
        out["environment"] = {"type": "constant", "radiance": _rgb(env.radiance)}
    elif isinstance(env, MapEnvironment):
        rotation = np.eye(4)
        rotation[:3, :3] = rotation_y(env.rotation)  # Mitsuba reads texel (u, v) in to_world^-1 of the direction
        out["environment"] = {
            "type": "envmap",
            "filename": env.file,
            "scale": env.intensity,
            "to_world": _matrix(mi, rotation),
        }
    return out


# --- the scene ------------------------------------------------------------------------------


def to_mitsuba(
    scene: Scene,
    meshes: dict[int, MeshArrays] | None = None,
    variant: str = VARIANT,
    bsdfs: dict[str, dict[str, Any]] | None = None,
) -> dict[str, Any]:
    """The scene as a dictionary for `mi.load_dict` (sets the Mitsuba variant if another is active).

    meshes: shape index -> that shape's arrays in its own coordinates (before its transform):
    (vertices (V, 3), indices (T, 3), normals (V, 3) or None), or an object with those
    attributes. Needed for ball, panel and mesh shapes; optional for spheres and planes.
    bsdfs: material name -> a Mitsuba BSDF dictionary used for it instead of converting it
    (the caller's choice of a stand-in, e.g. for a car paint, which has no exact equivalent).
    """
    mi = _mi(variant)
    meshes = meshes or {}
    out: dict[str, Any] = {
        "type": "scene",
        "integrator": _integrator(scene),
        "sensor": _sensor(mi, scene.camera, scene.render.spp, scene.render.seed),
    }
    loaded: dict[str, Any] = {}
    for index, shape in enumerate(scene.shapes):
        name = shape.material
        if name not in loaded:
            given = (bsdfs or {}).get(name)
            loaded[name] = mi.load_dict(given or bsdf(scene.materials[name], f"materials.{name}"))
        where = f"shapes[{index}]"
        if index in meshes:
            out[f"shape_{index}"] = mitsuba_mesh(mi, f"shape_{index}", meshes[index], shape.transform, loaded[name])
        else:
            out[f"shape_{index}"] = _analytic_shape(mi, shape, where, loaded[name])
    out.update(_lights(mi, scene))
    return out


__all__ = ["MitsubaConversionError", "bsdf", "mitsuba_mesh", "quad_to_world", "to_mitsuba"]
