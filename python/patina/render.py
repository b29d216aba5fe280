"""Rendering a scene: `patina render` and `patina preview`.

A parsed scene (`patina.scene_file`) becomes the C++ renderer's input here: every shape's
mesh (built in or read with trimesh) placed by its transform and concatenated into one
kd-tree, quad lights as emitting triangles, materials through `render_materials`, the
environment map read with OpenImageIO. The render runs on worker threads in C++; this
side shows progress (samples/s, rays/s, time left) and turns Ctrl-C into a cancel: the
passes that finished make a valid, noisier image, flagged as partial in its metadata.
Outputs are a float EXR (beauty + albedo, normal, depth and illuminance AOVs, metadata)
and a tone-mapped PNG, each written to a temporary file and renamed.
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from . import _core
from .envmap import LUMINOUS_EFFICACY, photometric_to_rgb
from .render_materials import core_material
from .scene_types import (
    BallShape,
    ConstantEnvironment,
    DiskLight,
    Light,
    LuminaireLight,
    MapEnvironment,
    MeshLight,
    MeshShape,
    PanelShape,
    PlaneShape,
    PointLight,
    QuadLight,
    Scene,
    Shape,
    SphereLight,
    SphereShape,
    SpotLight,
    SunLight,
)
from .widths import core_width

UNBOUNDED_DEPTH = 64  # a Mitsuba-style max_depth of -1 ("unbounded"); Russian roulette ends paths long before


@dataclass
class RenderResult:
    """A finished (or interrupted) render: linear images and what it took."""

    rgb: np.ndarray  # (H, W, 3) radiance, W/(m^2 sr)
    albedo: np.ndarray  # (H, W, 3)
    normal: np.ndarray  # (H, W, 3) world-space shading normal at the first hit
    depth: np.ndarray  # (H, W) distance to the first hit, inf where nothing was hit
    illuminance: np.ndarray  # (H, W) direct illuminance at the first hit, lux
    samples: np.ndarray  # (H, W) samples each pixel got
    spp: int
    seconds: float
    rays: int
    complete: bool
    simd_width: int
    threads: int


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
    """The shape's mesh in its own frame (a `patina.shapes.ShapeMesh`)."""
    from . import shapes

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
    n = np.linalg.norm(a, axis=1, keepdims=True)
    return np.divide(a, n, out=np.zeros_like(a), where=n > 0)


def _place(mesh: Any, m: np.ndarray) -> tuple[np.ndarray, ...]:
    """Vertices, triangles, normals and tangents moved by the 4x4 object-to-world matrix m.
    Normals go by the inverse transpose; a mirroring matrix also flips the winding, so the
    triangles' geometric normals keep pointing outwards."""
    lin, offset = m[:3, :3], m[:3, 3]
    v = np.asarray(mesh.vertices, np.float64) @ lin.T + offset
    n = _unit_rows(np.asarray(mesh.normals, np.float64) @ np.linalg.inv(lin))
    t = _unit_rows(np.asarray(mesh.tangents, np.float64) @ lin.T)
    f = np.asarray(mesh.indices, np.int64)
    if np.linalg.det(lin) < 0:
        f = f[:, [0, 2, 1]]
    return v, f, n, t


def _quad_triangles(light: QuadLight) -> tuple[np.ndarray, ...]:
    c, u, v = (np.asarray(x, np.float64) for x in (light.center, light.u, light.v))
    verts = np.array([c - u - v, c + u - v, c + u + v, c - u + v])
    faces = np.array([[0, 1, 2], [0, 2, 3]])  # both wound so that cross(e1, e2) is along u x v
    normal = np.tile(light.normal, (4, 1))
    tangent = np.tile(u / np.linalg.norm(u), (4, 1))
    return verts, faces, normal, tangent


def _core_light(light: Light) -> dict[str, Any]:
    """A scene light as a `RenderScene.add_light` dictionary (triangle ids added later)."""
    if isinstance(light, PointLight):
        return {"kind": "point", "position": list(light.position), "power": list(light.intensity), "two_sided": False}
    if isinstance(light, SpotLight):
        return {
            "kind": "spot",
            "position": list(light.position),
            "direction": list(light.direction),
            "power": list(light.intensity),
            "cos_inner": math.cos(math.radians(light.inner_angle)),
            "cos_outer": math.cos(math.radians(light.outer_angle)),
            "two_sided": False,
        }
    if isinstance(light, SunLight):
        half = math.radians(light.angular_diameter / 2)
        # uniform radiance L over a cone of half-angle d gives irradiance L pi sin^2 d facing it
        radiance = [e / (math.pi * math.sin(half) ** 2) for e in light.irradiance]
        return {
            "kind": "sun",
            "direction": list(light.direction),
            "half_angle": half,
            "power": radiance,
            "two_sided": False,
        }
    if isinstance(light, QuadLight):
        return {
            "kind": "quad",
            "position": list(light.center),
            "u": list(light.u),
            "v": list(light.v),
            "power": list(light.radiance),
            "two_sided": light.two_sided,
        }
    if isinstance(light, LuminaireLight):
        return _luminaire(light)
    if isinstance(light, DiskLight | SphereLight | MeshLight):
        two_sided = bool(getattr(light, "two_sided", False))
        return {"kind": "triangles", "power": list(light.radiance), "two_sided": two_sided}
    raise ValueError(f"light type '{light.type}' is not rendered yet")


def luminaire_axes(aim: Any, rotation_deg: float, kind: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The luminaire's x, y, z axes in the world. Type C: the nadir (-z) along `aim`; type B:
    the beam axis (+z) along `aim`. x is the world's +x (or +z, when aim is along x) made
    perpendicular to the axis, then turned by `rotation` degrees about it; y = z x x."""
    a = np.asarray(aim, np.float64) / np.linalg.norm(aim)
    z = -a if kind == "C" else a
    ref = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    x = ref - (ref @ z) * z
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    t = math.radians(rotation_deg)
    x, y = math.cos(t) * x + math.sin(t) * y, -math.sin(t) * x + math.cos(t) * y
    return x, y, z


def _luminaire(light: LuminaireLight) -> dict[str, Any]:
    from .luminaire import load_luminaire

    lum = load_luminaire(light.file)
    kind, h, v, candela = lum.grid()
    x, y, z = luminaire_axes(light.aim, light.rotation, kind)
    # an IES TILT table: the lamp's output against its tilt from the nadir-down position the
    # file was measured in, here the angle between `aim` and straight down
    tilt = lum.photometry.tilt
    factor = 1.0
    if tilt is not None and len(tilt.angles_deg):
        aim = np.asarray(light.aim, np.float64) / np.linalg.norm(light.aim)
        angle = math.degrees(math.acos(max(-1.0, min(1.0, -aim[1]))))
        factor = float(np.interp(angle, tilt.angles_deg, tilt.factors))
    # candela -> W/sr of Patina's radiometric RGB (683 lm/W of luminance), coloured
    per_cd = list(photometric_to_rgb(light.multiplier * factor, light.color))
    return {
        "kind": "goniometric",
        "position": list(light.position),
        "axis_x": x.tolist(),
        "axis_y": y.tolist(),
        "axis_z": z.tolist(),
        "type_b": kind == "B",
        "candela": _core.Grid2(h, v, np.ascontiguousarray(candela, np.float32)),
        "power": per_cd,
        "power_estimate": lum.flux() * light.multiplier * factor / LUMINOUS_EFFICACY,
        "two_sided": False,
    }


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
    from . import shapes

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


def camera_dict(scene: Scene) -> dict[str, Any]:
    cam = scene.camera
    right, up, forward = cam.basis()
    return {
        "position": [float(x) for x in cam.position],
        "forward": forward.tolist(),
        "right": right.tolist(),
        "up": up.tolist(),
        "tan_half_fov": math.tan(math.radians(cam.fov) / 2),
        "width": int(cam.width),
        "height": int(cam.height),
        "aperture_radius": float(cam.aperture_radius),
        "focus_distance": float(cam.focus_distance),
    }


class PreparedScene:
    """A scene loaded into the renderer: tree built, tables and environment read."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        geometry = _Geometry()
        names = list(scene.materials)
        cache: dict[str, Any] = {}
        core_materials = [core_material(scene.materials[name], cache) for name in names]
        for shape in scene.shapes:
            v, f, n, t = _place(shape_mesh(shape), shape.transform)
            geometry.add(v, f, n, t, names.index(shape.material))
        lights: list[dict[str, Any]] = []
        for light in scene.lights:
            entry = _core_light(light)
            mesh = _emitter_mesh(light)
            if mesh is not None:  # area lights are triangles the rays hit, and sampled as such
                core_materials.append({"kind": "emitter", "light": len(lights), "two_sided": entry["two_sided"]})
                ids = geometry.add(*mesh, len(core_materials) - 1)
                if entry["kind"] == "triangles":
                    entry["triangles"] = ids
            lights.append(entry)
        vertices, indices, normals, tangents, tri_material = geometry.arrays()
        self.triangles = len(indices)
        self.accel = _core.Accel(vertices, indices)
        self.core = _core.RenderScene(self.accel, indices, normals, tangents, tri_material, camera_dict(scene))
        for m in core_materials:
            self.core.add_material(m)
        for light in lights:
            self.core.add_light(light)
        env = scene.environment
        if isinstance(env, MapEnvironment):
            from .images import read_image

            rgb = np.ascontiguousarray(np.maximum(read_image(env.file)[..., :3], 0.0), dtype=np.float32)
            self.core.set_environment(rgb, [], float(env.intensity), math.radians(env.rotation))
        elif isinstance(env, ConstantEnvironment):
            self.core.set_environment(None, [float(x) for x in env.radiance], 1.0, 0.0)


def core_depth(scene: Scene) -> int:
    """The C++ integrator's bounce limit from the scene's (Mitsuba-style) max_depth and integrator."""
    if scene.render.integrator == "direct":
        return 1
    depth = scene.render.max_depth
    return UNBOUNDED_DEPTH if depth < 0 else max(1, depth - 1)


class _Progress:
    """One line on stderr: a bar, samples/s, rays/s, time left. Quiet when not a terminal."""

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled and sys.stderr.isatty()
        self.last = 0.0

    def update(self, p: dict[str, Any], final: bool = False) -> None:
        if not self.enabled or (not final and time.monotonic() - self.last < 0.25):
            return
        self.last = time.monotonic()
        done, total, secs = p["items_done"], max(1, p["items_total"]), max(p["seconds"], 1e-9)
        frac = done / total
        left = secs * (1 - frac) / frac if frac > 0 else float("nan")
        bar = "#" * int(30 * frac)
        eta = f"{left:5.1f} s left" if math.isfinite(left) else "  ... s left"
        sys.stderr.write(f"\r  [{bar:<30}] {100 * frac:5.1f}%  {p['rays'] / secs / 1e6:6.2f} Mrays/s  {eta}")
        if final:
            sys.stderr.write("\n")
        sys.stderr.flush()


def render(
    scene: Scene,
    threads: int = 0,
    width: int | None = None,
    progress: bool = False,
    prepared: PreparedScene | None = None,
) -> RenderResult:
    """Renders `scene` (its render settings as given: apply CLI overrides with
    `scene_file.with_overrides` first). width: SIMD width 1, 4 or 8 (None: the widest)."""
    prep = prepared or PreparedScene(scene)
    if (prep.scene.camera.width, prep.scene.camera.height) != (scene.camera.width, scene.camera.height):
        raise ValueError(
            f"the prepared scene renders {prep.scene.camera.width}x{prep.scene.camera.height}, this scene "
            f"{scene.camera.width}x{scene.camera.height}: prepare the scene as it is rendered"
        )
    simd = core_width(width)
    job = _core.RenderJob(
        prep.core,
        spp=scene.render.spp,
        max_depth=core_depth(scene),
        seed=scene.render.seed,
        threads=threads,
        width=simd,
    )
    bar = _Progress(progress)
    interrupted = False
    job.start()
    try:
        while not (p := job.progress())["finished"]:
            bar.update(p)
            time.sleep(0.05)
    except KeyboardInterrupt:
        interrupted = True
        job.cancel()
        if progress:
            sys.stderr.write("\n  interrupted: finishing the tiles in flight, keeping every finished pass\n")
    job.wait()
    p = job.progress()
    bar.update(p, final=True)
    images = job.resolve()
    resolved_threads = threads if threads > 0 else (os.cpu_count() or 1)
    complete = bool(p["finished"]) and not interrupted
    return RenderResult(
        rgb=images["rgb"],
        albedo=images["albedo"],
        normal=images["normal"],
        depth=images["depth"],
        illuminance=images["illuminance"],
        samples=images["samples"],
        spp=scene.render.spp,
        seconds=float(p["seconds"]),
        rays=int(p["rays"]),
        complete=complete,
        simd_width=simd if simd else _core.default_width(),
        threads=resolved_threads,
    )


def metadata(scene: Scene, result: RenderResult) -> dict[str, str | float | int]:
    from . import __version__
    from .scene_file import scene_to_json

    return {
        "patina:version": __version__,
        "patina:scene": json.dumps(scene_to_json(scene), separators=(",", ":")),
        "patina:scene_file": scene.path,
        "patina:spp": int(result.spp),
        "patina:samples_min": int(result.samples.min()) if result.samples.size else 0,
        "patina:integrator": scene.render.integrator,
        "patina:seed": int(scene.render.seed),
        "patina:seconds": float(result.seconds),
        "patina:rays": int(result.rays),
        "patina:simd_width": int(result.simd_width),
        "patina:threads": int(result.threads),
        "patina:complete": int(result.complete),
    }


def write_outputs(
    scene: Scene,
    result: RenderResult,
    exr_path: str,
    png_path: str | None,
    exposure: float = 0.0,
    curve: str = "filmic",
) -> None:
    """The EXR (beauty and AOVs, metadata) and the tone-mapped PNG, each written atomically."""
    from .images import write_exr, write_png

    depth = np.where(np.isfinite(result.depth), result.depth, 0.0).astype(np.float32)
    layers = {
        "beauty": result.rgb,
        "albedo": result.albedo,
        "normal": result.normal,
        "depth": depth,
        "illuminance": result.illuminance,
    }
    write_exr(exr_path, layers, metadata(scene, result))
    if png_path:
        write_png(png_path, result.rgb, exposure_stops=exposure, curve=curve)
