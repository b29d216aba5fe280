"""A parsed scene made into the C++ renderer's input (`_core.RenderScene`).

Every shape's mesh (built in or read with trimesh) placed by its transform and concatenated
into one kd-tree; area lights as emitting triangles the rays hit; materials through
`patina.render.materials`; the environment map read with OpenImageIO.

Lights cross to C++ as dictionaries of exactly the keys the renderer reads for their kind
(render/lights/, a type per kind; the bindings reject a missing or an unread key, naming
it), and with what follows from their geometry computed here, where the geometry is: a
quad's unit normal and area, the sun's cone and frame, an emissive mesh's triangle-area cdf, unit
directions. These are computed in float32 (float64 where the renderer summed in double) in
the very order of operations the renderer used to compute them in, so images are the same
bit for bit; the bindings only convert and check.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from patina.errors import FormatError
from patina.geometry import shapes
from patina.native import _core
from patina.photometry.luminaire import load_luminaire
from patina.photometry.placement import luminaire_axes, rgb_per_candela
from patina.render.images import read_image
from patina.render.materials import core_material
from patina.scene.reading import MAX_EMISSION, MAX_LENGTH, OVERFLOWS, similarity_scale
from patina.scene.types import (
    BallShape,
    CarpaintMaterial,
    ConstantEnvironment,
    DiskLight,
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
    RglMaterial,
    Scene,
    Shape,
    SphereLight,
    SphereShape,
    SpotLight,
    SunLight,
)


@dataclass
class _Geometry:
    vertices: list[np.ndarray] = field(default_factory=list)
    indices: list[np.ndarray] = field(default_factory=list)
    normals: list[np.ndarray] = field(default_factory=list)
    tangents: list[np.ndarray] = field(default_factory=list)
    materials: list[np.ndarray] = field(default_factory=list)
    count: int = 0
    triangles: int = 0

    def add(self, v: np.ndarray, f: np.ndarray, n: np.ndarray, t: np.ndarray, material: int) -> list[int]:
        """Appends a mesh; returns the global ids of its triangles."""
        ids = list(range(self.triangles, self.triangles + len(f)))
        self.triangles += len(f)
        self.vertices.append(v.astype(np.float32))
        self.indices.append(f.astype(np.int64) + self.count)
        self.normals.append(n.astype(np.float32))
        self.tangents.append(t.astype(np.float32))
        self.materials.append(np.full(len(f), material, np.int32))
        self.count += len(v)
        return ids

    def arrays(self) -> tuple[np.ndarray, ...]:
        if not self.vertices:
            return (
                np.zeros((0, 3), np.float32),
                np.zeros((0, 3), np.int32),
                np.zeros((0, 3), np.float32),
                np.zeros((0, 3), np.float32),
                np.zeros(0, np.int32),
            )
        c = lambda parts, dt: np.ascontiguousarray(np.concatenate(parts), dtype=dt)  # noqa: E731
        return (
            c(self.vertices, np.float32),
            c(self.indices, np.int32),
            c(self.normals, np.float32),
            c(self.tangents, np.float32),
            c(self.materials, np.int32),
        )


def shape_mesh(shape: Shape) -> Any:
    """The shape's mesh in its own frame (a `patina.geometry.shapes.ShapeMesh`)."""
    if isinstance(shape, SphereShape):
        return shapes.sphere(shape.radius)
    if isinstance(shape, PlaneShape):
        return shapes.plane(shape.size)
    if isinstance(shape, BallShape):
        return shapes.preview_ball()
    if isinstance(shape, PanelShape):
        return shapes.car_panel(shape.size)
    if isinstance(shape, MeshShape):
        return shapes.from_file(shape.file)
    raise ValueError(f"unknown shape {type(shape).__name__}")


def _unit_rows(a: np.ndarray) -> np.ndarray:
    with np.errstate(all="ignore"):
        n = np.linalg.norm(a, axis=1, keepdims=True)
        return np.divide(a, n, out=np.zeros_like(a), where=(n > 0) & np.isfinite(n))


def _check_mesh(scene: Scene, where: str, v: np.ndarray, f: np.ndarray, emits: bool) -> None:
    """A placed mesh as the renderer will hold it (float32 world coordinates) must be finite,
    within MAX_LENGTH, and have triangles of non-zero area; an emitter's area is what its
    light is sampled by, so a degenerate one would divide by zero."""
    v32 = v.astype(np.float32)
    if len(v) and not (np.isfinite(v32).all() and np.abs(v32).max() <= MAX_LENGTH):
        raise FormatError(scene.path, where, f"placed by its transform it reaches beyond {MAX_LENGTH:g} m: {OVERFLOWS}")
    with np.errstate(all="ignore"):
        p = v32.astype(np.float64)[f] if len(f) else np.zeros((0, 3, 3))
        area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    if not (area > 0).any():
        what = "emits from no area" if emits else "has no triangles of non-zero area"
        raise FormatError(scene.path, where, f"{what} (at the renderer's 32-bit precision)")


def _place(mesh: Any, m: np.ndarray) -> tuple[np.ndarray, ...]:
    """Vertices, triangles, normals and tangents moved by the 4x4 object-to-world matrix m.
    Normals go by the inverse transpose; a mirroring matrix also flips the winding, so the
    triangles' geometric normals keep pointing outwards."""
    lin, offset = m[:3, :3], m[:3, 3]
    with np.errstate(all="ignore"):  # out-of-range results are reported by _check_mesh, not as warnings
        v = np.asarray(mesh.vertices, np.float64) @ lin.T + offset
        n = _unit_rows(np.asarray(mesh.normals, np.float64) @ np.linalg.inv(lin))
        t = _unit_rows(np.asarray(mesh.tangents, np.float64) @ lin.T)
    f = np.asarray(mesh.indices, np.int64)
    if np.linalg.det(lin) < 0:
        f = f[:, [0, 2, 1]]
    return v, f, n, t


@dataclass
class _Spheres:
    """The analytic spheres, as `_core.Accel` takes them: (S, 4) centre and radius, (S, 3, 3)
    object frames (rows: the object's x, y, z axes in the world), and their materials."""

    rows: list[list[float]] = field(default_factory=list)
    frames: list[np.ndarray] = field(default_factory=list)
    materials: list[int] = field(default_factory=list)

    def add(self, scene: Scene, where: str, shape: SphereShape, material: int) -> None:
        m = shape.transform
        s = similarity_scale(m[:3, :3])
        if s is None:  # the reader lets none through
            raise FormatError(scene.path, where, "an analytic sphere's transform must be a similarity")
        centre, radius = m[:3, 3], shape.radius * s
        with np.errstate(all="ignore"):
            reach = np.abs(centre).max() + radius
        if not (np.isfinite(reach) and reach <= MAX_LENGTH and np.float32(radius) > 0):
            raise FormatError(
                scene.path, where, f"placed by its transform it reaches beyond {MAX_LENGTH:g} m: {OVERFLOWS}"
            )
        self.rows.append([*centre.tolist(), radius])
        self.frames.append((m[:3, :3] / s).T)
        self.materials.append(material)

    def accel_arguments(self) -> dict[str, np.ndarray]:
        if not self.rows:
            return {}
        return {
            "spheres": np.asarray(self.rows, np.float32),
            "sphere_frames": np.ascontiguousarray(np.asarray(self.frames), np.float32),
        }


def _quad_triangles(light: QuadLight) -> tuple[np.ndarray, ...]:
    c, u, v = (np.asarray(x, np.float64) for x in (light.center, light.u, light.v))
    verts = np.array([c - u - v, c + u - v, c + u + v, c - u + v])
    faces = np.array([[0, 1, 2], [0, 2, 3]])  # both wound so that cross(e1, e2) is along u x v
    normal = np.tile(light.normal, (4, 1))
    tangent = np.tile(u / np.linalg.norm(u), (4, 1))
    return verts, faces, normal, tangent


_F32 = np.float32


def _f32(v: Any) -> list[np.float32]:
    return [_F32(x) for x in v]


def unit_vector32(v: Any) -> list[float]:
    """v / |v| in float32, each product, sum, root and quotient rounded to float32 in the
    renderer's order (((x x + y y) + z z), then each component divided by the root)."""
    x, y, z = _f32(v)
    length = np.sqrt(x * x + y * y + z * z)
    if not (length > 0 and np.isfinite(length)):
        raise ValueError("a direction must be a non-zero vector")
    return [float(x / length), float(y / length), float(z / length)]


def quad_normal_area(u: Any, v: Any) -> tuple[list[float], float]:
    """A quad light's unit normal, normalize(u x v), and its area 4 |u x v| (u, v the half
    edges), in float32 in the renderer's order."""
    u0, u1, u2 = _f32(u)
    v0, v1, v2 = _f32(v)
    n = (u1 * v2 - u2 * v1, u2 * v0 - u0 * v2, u0 * v1 - u1 * v0)
    length = np.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2])
    if not (length > 0 and np.isfinite(length)):
        raise ValueError("a quad light needs non-parallel u and v")
    return [float(c / length) for c in n], float(_F32(4) * length)


def sun_cone(half_angle: float) -> tuple[float, float]:
    """(cos d, 1 - cos d) of the sun's angular radius d (radians, taken as a float32 first),
    1 - cos d as 2 sin^2(d / 2) without cancellation; each rounded to float32 at the end."""
    half = float(_F32(half_angle))
    if not 0 < half < 1.5:
        raise ValueError("the sun's disc: 0 < half_angle < 1.5 rad")
    s = math.sin(half / 2)
    return float(_F32(math.cos(half))), float(_F32(2 * s * s))


def orthonormal_frame32(n: Any) -> tuple[list[float], list[float]]:
    """A tangent t and bitangent b around unit n (Duff et al. 2017, "Building an orthonormal
    basis, revisited"), in float32 exactly as render/scene.cpp's orthonormal_frame."""
    x, y, z = _f32(n)
    sign = _F32(math.copysign(1.0, float(z)))
    a = _F32(-1) / (sign + z)
    c = x * y * a
    t = (_F32(1) + sign * x * x * a, sign * c, -sign * x)
    b = (c, sign + y * y * a, -y)
    return [float(e) for e in t], [float(e) for e in b]


def triangle_area_cdf(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, float]:
    """An emissive mesh's area cdf (len(faces) + 1 float32 values from 0 to exactly 1) and
    its total area, for sampling its triangles by area. As the renderer holds them: edges
    of the float32 vertices in float32, their cross product, lengths and running sum in
    float64, summed in order."""
    p = np.asarray(vertices).astype(np.float32)[np.asarray(faces)]
    e1 = (p[:, 1] - p[:, 0]).astype(np.float64)
    e2 = (p[:, 2] - p[:, 0]).astype(np.float64)
    c = np.cross(e1, e2)
    area = 0.5 * np.sqrt(c[:, 0] * c[:, 0] + c[:, 1] * c[:, 1] + c[:, 2] * c[:, 2])
    running = np.cumsum(area)  # sequential, as a loop would add
    total = float(running[-1]) if len(running) else 0.0
    if not (total > 0 and math.isfinite(total)):
        raise ValueError("an emissive mesh needs a positive area")
    cdf = np.empty(len(area) + 1, np.float32)
    cdf[0] = 0.0
    cdf[1:] = running / total
    cdf[-1] = 1.0
    return cdf, float(_F32(total))


def _core_light(light: Light) -> dict[str, Any]:
    """A scene light as a `RenderScene.add_light` dictionary; an emissive mesh's triangles
    and area cdf are added once its triangles are placed."""
    if isinstance(light, PointLight):
        return {"kind": "point", "position": list(light.position), "power": list(light.intensity)}
    if isinstance(light, SpotLight):
        return {
            "kind": "spot",
            "position": list(light.position),
            "direction": unit_vector32(light.direction),
            "power": list(light.intensity),
            "cos_inner": math.cos(math.radians(light.inner_angle)),
            "cos_outer": math.cos(math.radians(light.outer_angle)),
        }
    if isinstance(light, SunLight):
        half = math.radians(light.angular_diameter / 2)
        # uniform radiance L over a cone of half-angle d gives irradiance L pi sin^2 d facing it
        radiance = [e / (math.pi * math.sin(half) ** 2) for e in light.irradiance]
        direction = unit_vector32(light.direction)
        cos_sun, one_minus_cos = sun_cone(half)
        frame_t, frame_b = orthonormal_frame32(direction)
        return {
            "kind": "sun",
            "direction": direction,
            "cos_sun": cos_sun,
            "sun_one_minus_cos": one_minus_cos,
            "frame_t": frame_t,
            "frame_b": frame_b,
            "power": radiance,
        }
    if isinstance(light, QuadLight):
        normal, area = quad_normal_area(light.u, light.v)
        return {
            "kind": "quad",
            "position": list(light.center),
            "u": list(light.u),
            "v": list(light.v),
            "normal": normal,
            "area": area,
            "power": list(light.radiance),
            "two_sided": light.two_sided,
        }
    if isinstance(light, LuminaireLight):
        return _luminaire(light)
    if isinstance(light, DiskLight | SphereLight | MeshLight):
        two_sided = bool(getattr(light, "two_sided", False))
        return {"kind": "triangles", "power": list(light.radiance), "two_sided": two_sided}
    raise ValueError(f"light type '{light.type}' is not rendered yet")


def _luminaire(light: LuminaireLight) -> dict[str, Any]:
    lum = load_luminaire(light.file)
    kind, h, v, candela = lum.grid()
    x, y, z = luminaire_axes(light.aim, light.rotation, kind)
    per_cd = list(rgb_per_candela(lum, light.aim, light.multiplier, light.color))
    peak = float(np.max(candela, initial=0.0)) * max(per_cd)
    if not peak <= MAX_EMISSION:
        raise FormatError(
            light.file,
            "candela",
            f"{peak:g} W/sr at its peak (times the multiplier) exceeds {MAX_EMISSION:g}: {OVERFLOWS}",
        )
    return {
        "kind": "goniometric",
        "position": list(light.position),
        "axis_x": x.tolist(),
        "axis_y": y.tolist(),
        "axis_z": z.tolist(),
        "type_b": kind == "B",
        "candela": _core.Grid2(h, v, np.ascontiguousarray(candela, np.float32)),
        "power": per_cd,
    }


def _peak(power: Any) -> float:
    """The largest channel of a light's emission (W/sr, W/m^2/sr, or W/sr per cd times the
    largest candela for a luminaire); NaN counts as too large."""
    values = [float(x) for x in power]
    return math.inf if any(math.isnan(x) for x in values) else max(values)


DISK_SEGMENTS = 128


def _disk_triangles(light: DiskLight) -> tuple[np.ndarray, ...]:
    """A fan of DISK_SEGMENTS triangles, its radius raised so its area is exactly pi r^2."""
    n = np.asarray(light.normal, np.float64)
    t = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t)
    b = np.cross(n, t)
    k = DISK_SEGMENTS
    r = light.radius * math.sqrt(2 * math.pi / (k * math.sin(2 * math.pi / k)))
    phi = 2 * math.pi * np.arange(k) / k
    rim = np.asarray(light.center) + r * (np.cos(phi)[:, None] * t + np.sin(phi)[:, None] * b)
    verts = np.vstack([np.asarray(light.center, np.float64), rim])
    faces = np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])  # counter-clockwise about n
    return verts, faces, np.tile(n, (k + 1, 1)), np.tile(t, (k + 1, 1))


def _emitter_mesh(light: Light) -> tuple[np.ndarray, ...] | None:
    """The triangles of an area light (vertices, faces, normals, tangents), None for the others."""
    if isinstance(light, QuadLight):
        return _quad_triangles(light)
    if isinstance(light, DiskLight):
        return _disk_triangles(light)
    if isinstance(light, SphereLight):
        m = np.eye(4)
        m[:3, 3] = light.center
        return _place(shapes.sphere(light.radius), m)
    if isinstance(light, MeshLight):
        return _place(shapes.from_file(light.file), light.transform)
    return None


def core_camera(scene: Scene) -> _core.Camera:
    """The scene's camera as the renderer takes it: its frame and the tangent of half its fov."""
    cam = scene.camera
    right, up, forward = cam.basis()
    return _core.Camera(
        position=[float(x) for x in cam.position],
        forward=forward.tolist(),
        right=right.tolist(),
        up=up.tolist(),
        tan_half_fov=math.tan(math.radians(cam.fov) / 2),
        width=int(cam.width),
        height=int(cam.height),
        aperture_radius=float(cam.aperture_radius),
        focus_distance=float(cam.focus_distance),
    )


# Memory a render holds per pixel at its peak: the film's sums (13 doubles: rgb, albedo,
# normal, illuminance, depth and two weights) while it resolves into the images handed to
# Python (12 float32: rgb, albedo, normal, depth, illuminance, samples). The outputs then
# need 44 bytes a pixel more (the EXR's one float32 buffer), the film being freed by then.
FILM_BYTES_PER_PIXEL = 13 * 8
IMAGE_BYTES_PER_PIXEL = 12 * 4
RENDER_BYTES_PER_PIXEL = FILM_BYTES_PER_PIXEL + IMAGE_BYTES_PER_PIXEL
MEMORY_SHARE = 0.8  # of the available memory a render may plan on; the rest is the scene's and the system's


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (Linux: MemAvailable), None if unknown."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):
        return None


def render_memory(width: int, height: int) -> int:
    """Bytes a width x height render needs at its peak (film, images, outputs)."""
    return width * height * RENDER_BYTES_PER_PIXEL


def check_render_memory(scene: Scene) -> None:
    """Before any work: the image fits in memory, or a FormatError saying how large it may be
    (instead of a MemoryError once the film or the outputs are allocated). The radiance
    cache's is stated, not checked (patina.render.cache_memory: its bound is a cache point a
    pixel, which scenes rarely come near)."""
    w, h = scene.camera.width, scene.camera.height
    available = available_memory()
    if available is None:
        return
    budget = int(available * MEMORY_SHARE)
    need = render_memory(w, h)
    if need > budget:
        side = math.isqrt(max(budget // RENDER_BYTES_PER_PIXEL, 1))
        raise FormatError(
            scene.path,
            "camera.width x camera.height (or --width, --height)",
            f"a {w}x{h} render needs about {need / 2**30:.1f} GiB ({RENDER_BYTES_PER_PIXEL} bytes a pixel for the "
            f"film and its images); {budget / 2**30:.1f} GiB may be used here ({MEMORY_SHARE:.0%} of the memory "
            f"available): render at most about {side}x{side} pixels",
        )


def _reads_rgl(m: Material) -> bool:
    return isinstance(m, RglMaterial) or (isinstance(m, CarpaintMaterial) and isinstance(m.base, RglMaterial))


def _core_materials(scene: Scene) -> list[dict[str, Any]]:
    """The scene's materials as the renderer takes them, in the order of scene.materials. An RGL
    file the renderer cannot take is told under the scene file and the material's name: the
    file is read here, after the scene, and the user looks for it in the scene."""
    tables: dict[str, Any] = {}
    out = []
    for name, m in scene.materials.items():
        try:
            out.append(core_material(m, tables))
        except ValueError as e:
            if not _reads_rgl(m):
                raise
            raise FormatError(scene.path, f"materials.{name}", str(e)) from None
    return out


class PreparedScene:
    """A scene loaded into the renderer: tree built, tables and environment read."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        geometry = _Geometry()
        names = list(scene.materials)
        core_materials = _core_materials(scene)
        spheres = _Spheres()
        for i, shape in enumerate(scene.shapes):
            if isinstance(shape, SphereShape) and shape.analytic:
                spheres.add(scene, f"shapes[{i}]", shape, names.index(shape.material))
                continue
            try:
                placed = _place(shape_mesh(shape), shape.transform)
            except ValueError as e:  # a shape too small to tessellate
                raise FormatError(scene.path, f"shapes[{i}]", str(e)) from None
            v, f, n, t = placed
            _check_mesh(scene, f"shapes[{i}]", v, f, emits=False)
            geometry.add(v, f, n, t, names.index(shape.material))
        lights: list[dict[str, Any]] = []
        for i, light in enumerate(scene.lights):
            try:
                entry = _core_light(light)
            except FormatError:  # a luminaire file's own problem, already naming that file
                raise
            except ValueError as e:  # geometry the renderer cannot use (the reader lets none through)
                raise FormatError(scene.path, f"lights[{i}]", str(e)) from None
            if _peak(entry["power"]) > MAX_EMISSION:
                raise FormatError(
                    scene.path, f"lights[{i}]", f"its emission reaches {_peak(entry['power']):g} W: {OVERFLOWS}"
                )
            try:
                mesh = _emitter_mesh(light)
            except ValueError as e:
                raise FormatError(scene.path, f"lights[{i}]", str(e)) from None
            if mesh is not None:  # area lights are triangles the rays hit, and sampled as such
                _check_mesh(scene, f"lights[{i}]", mesh[0], mesh[1], emits=True)
                core_materials.append({"kind": "emitter", "light": len(lights)})
                ids = geometry.add(*mesh, len(core_materials) - 1)
                if entry["kind"] == "triangles":
                    entry["triangles"] = np.asarray(ids, np.int32)
                    entry["area_cdf"], entry["area"] = triangle_area_cdf(mesh[0], mesh[1])
            lights.append(entry)
        vertices, indices, normals, tangents, tri_material = geometry.arrays()
        self.triangles = len(indices)
        self.spheres = len(spheres.rows)
        # primitives: the triangles, then the analytic spheres (render/accel/spheres.h)
        tri_material = np.concatenate([tri_material, np.asarray(spheres.materials, np.int32)])
        # what was handed to C++, kept for inspection and tests (the core keeps its own copies)
        self.core_materials = core_materials
        self.core_lights = lights
        self.arrays = (indices, normals, tangents, tri_material)
        self.accel = _core.Accel(vertices, indices, **spheres.accel_arguments())
        self.core = _core.RenderScene(self.accel, indices, normals, tangents, tri_material, core_camera(scene))
        for m in core_materials:
            self.core.add_material(m)
        for light in lights:
            self.core.add_light(light)
        env = scene.environment
        if isinstance(env, MapEnvironment):
            rgb = np.ascontiguousarray(np.maximum(read_image(env.file)[..., :3], 0.0), dtype=np.float32)
            with np.errstate(all="ignore"):
                peak = float(np.max(rgb, initial=0.0)) * float(env.intensity)
            if not peak <= MAX_EMISSION:  # also NaN texels
                raise FormatError(
                    env.file,
                    "pixels",
                    f"radiance up to {peak:g} (times environment.intensity) exceeds {MAX_EMISSION:g}: {OVERFLOWS}",
                )
            self.core.set_environment(rgb, [], float(env.intensity), math.radians(env.rotation))
        elif isinstance(env, ConstantEnvironment):
            self.core.set_environment(None, [float(x) for x in env.radiance], 1.0, 0.0)
