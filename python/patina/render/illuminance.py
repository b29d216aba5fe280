"""Illuminance on a grid of sensor points: `patina illuminance SCENE.json --grid SPEC [--indirect]`.

What a lighting engineer checks against a standard (a pitch, a road, a workplane, an
interior's desks, a cockpit's instruments): the illuminance in lux on horizontal sensors at
a height. Direct: from every light of the scene (luminaires, area lights, the sun, the
environment), shadowed by the scene's geometry, by the renderer's own light sampling and
shadow-ray packets. With `indirect` (DIALux's "with interreflections"): plus the light the
scene reflects, by the path tracer -- per sample one sensor ray over the cosine-weighted
hemisphere continued as a path whose first hit's emission is not counted (light sampling
counted it), so direct + indirect is every light once. Reported: minimum, mean and maximum,
and the uniformity ratios U0 = Emin / Eavg and Ud = Emin / Emax.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import os
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.atomic import write_text
from patina.errors import FormatError
from patina.lighting.direct import PlacedSource, direct_illuminance, is_delta
from patina.lighting.indirect_cache import CacheSettings, cached_indirect
from patina.lighting.plan import write_plan
from patina.lighting.scene_luminaires import plan_luminaires
from patina.lighting.sensors import make_sensors, parse_sensor
from patina.native import _core
from patina.progress import Progress
from patina.render.prepare import PreparedScene
from patina.scene.types import Scene
from patina.widths import core_width

MAX_SAMPLES = 1 << 20  # light samples per sensor: far beyond converged; more is a typo
CHUNK_SENSORS = 16384  # sensors per call: a few seconds of work at the default samples at most


@dataclass(frozen=True)
class Grid:
    """nx x nz sensors from (x0, z0) to (x1, z1) (inclusive) at height y, facing up (+y) or down."""

    x0: float
    z0: float
    x1: float
    z1: float
    nx: int
    nz: int
    y: float = 0.0
    facing_up: bool = True

    def points(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x (nx,), z (nz,), points (nz * nx, 3)) rows of constant z."""
        x = np.linspace(self.x0, self.x1, self.nx)
        z = np.linspace(self.z0, self.z1, self.nz)
        zz, xx = np.meshgrid(z, x, indexing="ij")
        pts = np.stack([xx.ravel(), np.full(xx.size, self.y), zz.ravel()], axis=1)
        return x, z, np.ascontiguousarray(pts, np.float32)


def parse_grid(spec: str, height: float = 0.0, facing: str = "up") -> Grid:
    """'X0,Z0,X1,Z1,NX,NZ' (metres, sensor counts) -> Grid; FormatError naming the option."""
    parts = spec.split(",")
    try:
        if len(parts) != 6:
            raise ValueError
        x0, z0, x1, z1 = (float(v) for v in parts[:4])
        nx, nz = int(parts[4]), int(parts[5])
    except ValueError:
        raise FormatError("command line", "--grid", f"expected X0,Z0,X1,Z1,NX,NZ, got '{spec}'") from None
    if not all(np.isfinite([x0, z0, x1, z1, height])):
        raise FormatError("command line", "--grid", "coordinates must be finite")
    if not (1 <= nx <= 4096 and 1 <= nz <= 4096):
        raise FormatError("command line", "--grid", f"sensor counts must be 1 to 4096, got {nx} x {nz}")
    if facing not in ("up", "down"):
        raise FormatError("command line", "--facing", f"expected up or down, got '{facing}'")
    return Grid(x0, z0, x1, z1, nx, nz, height, facing == "up")


@dataclass
class IlluminanceReport:
    grid: Grid
    lux: np.ndarray  # (nz, nx)
    samples: int
    indirect: bool = False  # lux includes interreflections
    exact_lights: int = 0  # point, spot and goniometric lights summed exactly (no sampling)
    sensor: str = "up"  # up, down, vertical:AZ, cylindrical, semicylindrical:AZ (lighting.sensors)

    @property
    def stats(self) -> dict[str, float]:
        e = self.lux
        mean, lo, hi = float(e.mean()), float(e.min()), float(e.max())
        return {
            "min_lux": lo,
            "mean_lux": mean,
            "max_lux": hi,
            "u0": lo / mean if mean > 0 else 0.0,
            "ud": lo / hi if hi > 0 else 0.0,
        }

    def as_json(self) -> dict[str, Any]:
        g = self.grid
        return {
            "grid": {
                "x0": g.x0,
                "z0": g.z0,
                "x1": g.x1,
                "z1": g.z1,
                "nx": g.nx,
                "nz": g.nz,
                "height": g.y,
                "facing": "up" if g.facing_up else "down",
            },
            "samples_per_sensor": self.samples,
            "exact_lights": self.exact_lights,
            "sensor": self.sensor,
            "interreflections": self.indirect,
            **self.stats,
            "lux": self.lux.tolist(),
        }


def compute(
    scene: Scene,
    grid: Grid,
    samples: int = 256,
    threads: int = 0,
    width: int | None = None,
    progress: bool = False,
    indirect: bool = False,
    sensor: str | None = None,
    indirect_cache: bool = False,
) -> IlluminanceReport:
    """The grid's illuminance. Point, spot and goniometric lights: exact, the finite sum of
    patina.lighting.direct with a shadow ray each (no sampling; deterministic). The other
    lights (area, sun, environment): by `samples` light samples per sensor, and with
    `indirect` the interreflections of every light by `samples` sensor paths of at most
    the vertices of a camera path of render.max_depth; both through `_core.sensor_illuminance`, CHUNK_SENSORS
    sensors per call (progress shown with `progress`, Ctrl-C stops between chunks). Each
    chunk's sensors are numbered from 0 in its random streams, so the result depends on the
    seed and the chunk size only (not on threads or width). With `indirect_cache` the
    interreflections come from the radiance cache instead (patina.lighting.indirect_cache,
    every sensor at once)."""
    _, _, pts = grid.points()
    kind = parse_sensor(sensor) if sensor else ("up" if grid.facing_up else "down", None)
    sensors = make_sensors(pts, *kind)
    exact = [light for light in scene.lights if is_delta(light)]
    sampled = [light for light in scene.lights if not is_delta(light)]
    prepared = PreparedScene(scene)
    sources, offset = [PlacedSource.of(light) for light in exact], ray_offset(prepared)
    lux = np.zeros(len(pts))
    rest = None
    if sampled or scene.environment is not None:
        rest = PreparedScene(dataclasses.replace(scene, lights=tuple(sampled))) if exact else prepared
    if sensors.kind != "planar" and (rest is not None or indirect):
        # the sampling kernel measures on planes: a cylinder's mean it cannot give
        raise FormatError(
            "command line",
            "--sensor",
            f"{kind[0]} sensors sum point, spot and goniometric luminaires only; this scene has "
            + ("--indirect" if indirect else "area lights, the sun or an environment"),
        )
    if indirect_cache and not indirect:
        raise FormatError("command line", "--indirect-cache", "needs --indirect (it computes the interreflections)")
    normals = np.ascontiguousarray(sensors.normals, np.float32)
    simd, seed = core_width(width), scene.render.seed
    depth = sensor_depth(scene) if indirect else 0
    paths = indirect and not indirect_cache
    # a chunk of sensor paths costs about a camera path per sample: show progress sooner
    chunk = CHUNK_SENSORS // 16 if paths else CHUNK_SENSORS
    chunks = range(0, len(pts), chunk)
    with Progress(len(pts), "illuminance", unit="sensor", enabled=progress and len(chunks) > 1) as bar:
        for begin in chunks:
            end = min(begin + chunk, len(pts))
            lux[begin:end] = direct_illuminance(
                sources, sensors.part(begin, end), prepared.accel, offset, width=simd, threads=threads
            )
            part = pts[begin:end], normals[begin:end], samples, seed, simd, threads
            if rest is not None:
                lux[begin:end] += _core.sensor_illuminance(rest.core, *part, 0)
            if paths:
                lux[begin:end] += path_interreflections(prepared, *part, depth)
            bar.update(end)
    if indirect_cache:
        settings = CacheSettings(depth, seed, width=simd, threads=threads)
        lux += cached_indirect(prepared.core, np.asarray(pts), normals, settings).lux
    name = kind[0] + (f":{kind[1]:g}" if kind[1] is not None else "")
    return IlluminanceReport(grid, lux.reshape(grid.nz, grid.nx), samples, indirect, len(exact), name)


def path_interreflections(prepared: PreparedScene, points, normals, samples, seed, width, threads, depth):
    """The interreflections alone at planar sensors (lux, float64), by `samples` sensor paths of
    at most `depth` vertices: the kernel adds them to its direct estimate, whose random streams
    are the same with or without them (render/integrators/sensors_impl.h), so the difference is
    the indirect part of every light, the delta lights' included."""
    part = points, normals, samples, seed, width, threads
    total = np.asarray(_core.sensor_illuminance(prepared.core, *part, depth), np.float64)
    return total - _core.sensor_illuminance(prepared.core, *part, 0)


def ray_offset(prepared: PreparedScene) -> float:
    """The renderer's secondary-ray offset (render/scene.cpp): 2e-5 of the scene's largest
    coordinate or radius, at least 1e-5."""
    tri = np.asarray(prepared.accel.triangles)
    extent = float(np.abs(tri).max()) if tri.size else 0.0
    return max(1e-5, 2e-5 * max(extent, float(prepared.core.scene_radius)))


def sensor_depth(scene: Scene) -> int:
    """The max_depth of the sensor paths (`_core.sensor_illuminance`): the scene's camera
    paths' under the path integrator (render.max_depth in segments, whatever render.integrator
    says), so a sensor sees what a camera at its place would, minus the emitters."""
    return scene.render.max_depth


def write_csv(report: IlluminanceReport, path: str) -> None:
    _, _, pts = report.grid.points()
    out = io.StringIO()
    w = csv.writer(out)
    w.writerow(["x", "y", "z", "lux"])
    for p, e in zip(pts, report.lux.ravel()):
        w.writerow([f"{p[0]:.6g}", f"{p[1]:.6g}", f"{p[2]:.6g}", f"{e:.6g}"])
    write_text(path, out.getvalue())


def write_json(report: IlluminanceReport, path: str) -> None:
    write_text(path, json.dumps(report.as_json(), indent=1) + "\n")


def write_png(report: IlluminanceReport, path: str, title: str = "", scene: Scene | None = None) -> None:
    """The plan (patina.lighting.plan): false colour with each cell centred on its sensor,
    iso-lux lines, the scene's point, spot and goniometric luminaires, the stats in the title."""
    x, z, _ = report.grid.points()
    st = report.stats
    heading = (
        f"{title}\nEmin {st['min_lux']:.1f}  Eavg {st['mean_lux']:.1f}  Emax {st['max_lux']:.1f} lx  "
        f"U0 {st['u0']:.2f}  Ud {st['ud']:.2f}"
    )
    write_plan(path, report.lux, x, z, heading, plan_luminaires(scene) if scene is not None else None)


def summary(report: IlluminanceReport, scene_path: str) -> str:
    g, st = report.grid, report.stats
    return "\n".join(
        [
            f"{os.path.basename(scene_path)}: {'total' if report.indirect else 'direct'} illuminance "
            f"on {g.nx} x {g.nz} sensors at y = {g.y:g} m "
            f"({report.sensor}), x {g.x0:g}..{g.x1:g}, z {g.z0:g}..{g.z1:g} m "
            f"({report.exact_lights} point, spot or goniometric lights summed exactly; "
            f"{report.samples} light samples{' and sensor paths' if report.indirect else ''} per sensor "
            "for the rest)",
            f"  Emin  {st['min_lux']:10.2f} lux",
            f"  Eavg  {st['mean_lux']:10.2f} lux",
            f"  Emax  {st['max_lux']:10.2f} lux",
            f"  U0 = Emin / Eavg  {st['u0']:.3f}",
            f"  Ud = Emin / Emax  {st['ud']:.3f}",
        ]
    )
