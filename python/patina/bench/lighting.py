"""`patina bench --only lighting` (issue 32): the lighting calculations' speed.

`lighting.direct.sensors_per_s.w<N>`: the exact direct illuminance (patina.lighting.direct, the
native kernel of render/lighting/direct_illuminance.h) of 10^5 horizontal sensors (`--quick`:
4096) under 20 luminaires (the bundled downlight IES and street-light EULUMDAT files alternating
on a 5 x 4 grid, 3.5 to 5 m up) over a 40 x 30 m floor with spheres and balls casting shadows:
one candela lookup and one shadow ray per luminaire per sensor (packets through the scene's
BVH, built on the warm-up run), one thread, at width N against width 1; value the sensors per
second at width N.

`lighting.indirect.vs_path_equal_error`: the interreflected illuminance of horizontal sensors
on the bundled office's working plane (materials/scenes/office-en12464.json, a 0.1 m grid over
its 6 x 4 m room: 2400 sensors; `--quick`: 0.25 m) from the radiance cache
(patina.lighting.indirect_cache: cache points at some sensors, the others gathering from them)
against the sensor paths (`_core.sensor_illuminance`) at equal relMSE over the sensors, both
against a reference of 2048 sensor paths a sensor (another seed), on every core; ratio = the
paths' time at the cache's relMSE (log-log between the ladder's levels) over the cache's time.
"""

from __future__ import annotations

import functools
import os
from dataclasses import dataclass

import numpy as np

from patina.bench.cache import MAX_REPEAT
from patina.bench.convergence import ErrorCurve
from patina.bench.records import Record, median_times, median_times_and_values, simd_widths
from patina.bundled import materials_path
from patina.lighting.direct import PlacedSource, direct_illuminance
from patina.lighting.indirect_cache import RESOLUTION, CacheSettings, cached_indirect
from patina.lighting.sensors import make_sensors
from patina.native import _core
from patina.render.illuminance import ray_offset, sensor_depth
from patina.render.prepare import PreparedScene
from patina.scene.reading import load_scene, parse_scene

SENSORS, QUICK_SENSORS = 100_000, 4096
INDIRECT_SCENE = "office-en12464"


def luminaire_field() -> tuple[object, list[PlacedSource]]:
    """The direct record's scene: 20 luminaires over a floor with occluders."""
    mat = materials_path()
    files = [os.path.join(mat, "luminaires", name) for name in ("downlight.ies", "streetlight.ldt")]
    lights = [
        {"type": "luminaire", "file": files[(i + j) % 2], "position": [-16 + 8 * i, 3.5 + 0.5 * (j % 4), -12 + 8 * j]}
        for i in range(5)
        for j in range(4)
    ]
    shapes = [{"type": "plane", "material": "m", "size": [40, 30]}]
    shapes += [
        {"type": "sphere", "material": "m", "radius": 0.8, "transform": {"translate": [-12 + 6 * k, 1.2, 2 - k]}}
        for k in range(5)
    ]
    shapes += [{"type": "ball", "material": "m", "transform": {"translate": [-10 + 5 * k, 1, -6]}} for k in range(5)]
    obj = {
        "version": 1,
        "camera": {"position": [0, 20, 20], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "materials": {"m": {"type": "lambert", "albedo": 0.5}},
        "shapes": shapes,
        "lights": lights,
    }
    scene = parse_scene(obj, os.path.join(mat, "bench.json"))
    return scene, [PlacedSource.of(light) for light in scene.lights]


def _direct_records(repeat: int, quick: bool) -> list[Record]:
    scene, sources = luminaire_field()
    prepared = PreparedScene(scene)
    n = QUICK_SENSORS if quick else SENSORS
    side = int(np.ceil(np.sqrt(n)))
    x, z = np.meshgrid(np.linspace(-19.5, 19.5, side), np.linspace(-14.5, 14.5, side))
    pts = np.stack([x.ravel(), np.full(x.size, 0.75), z.ravel()], axis=1)[:n]
    sensors = make_sensors(pts, "up", None)
    run = functools.partial(direct_illuminance, sources, sensors, prepared.accel, ray_offset(prepared), threads=1)
    records = []
    for w in simd_widths():
        t1, tw = median_times([functools.partial(run, width=1), functools.partial(run, width=w)], repeat)
        records.append(
            Record(
                f"lighting.direct.sensors_per_s.w{w}",
                f"exact direct illuminance, {n} sensors x {len(sources)} luminaires (IES and EULUMDAT) with "
                f"occluders, width {w}, 1 thread",
                "the same at width 1",
                t1 / tw,
                n / tw,
                "sensors/s",
            )
        )
    return records


@dataclass(frozen=True)
class IndirectSizes:
    """The indirect record's sizes: the sensor grid's step (m), the reference's and the path
    ladder's sensor paths per sensor, and the cache points' hemisphere resolution."""

    step: float
    reference_spp: int
    ladder: tuple[int, ...]
    resolution: int


INDIRECT_FULL = IndirectSizes(0.1, 2048, (64, 256, 1024), RESOLUTION)
INDIRECT_QUICK = IndirectSizes(0.25, 256, (16, 64), 8)


def office_sensors(step: float) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal sensors on the office's working plane (0.75 m), `step` apart over its
    6 x 4 m room, cell centres: points and normals, float32."""
    x, z = np.meshgrid(np.arange(-3 + step / 2, 3, step), np.arange(-2 + step / 2, 2, step))
    points = np.stack([x.ravel(), np.full(x.size, 0.75), z.ravel()], axis=1)
    normals = np.tile([0.0, 1.0, 0.0], (len(points), 1))
    return np.ascontiguousarray(points, np.float32), np.ascontiguousarray(normals, np.float32)


def path_indirect(prepared: PreparedScene, points, normals, samples: int, seed: int, depth: int) -> np.ndarray:
    """The sensor paths' interreflected lux: the kernel's total minus its direct estimate
    (the same streams), as `patina illuminance --indirect` takes it."""
    total = np.asarray(_core.sensor_illuminance(prepared.core, points, normals, samples, seed, 0, 0, depth))
    return total - np.asarray(_core.sensor_illuminance(prepared.core, points, normals, samples, seed, 0, 0, 0))


def _relmse(estimate: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean(((estimate - ref) / ref) ** 2))


def _indirect_record(repeat: int, quick: bool) -> list[Record]:
    sizes = INDIRECT_QUICK if quick else INDIRECT_FULL
    scene = load_scene(materials_path("scenes", f"{INDIRECT_SCENE}.json"))
    prepared = PreparedScene(scene)
    depth = sensor_depth(scene)
    points, normals = office_sensors(sizes.step)
    ref = path_indirect(prepared, points, normals, sizes.reference_spp, 1, depth)
    runs = [functools.partial(path_indirect, prepared, points, normals, n, 0, depth) for n in sizes.ladder]
    settings = CacheSettings(depth, 0, sizes.resolution)
    runs.append(lambda: cached_indirect(prepared.core, points, normals, settings).lux)
    times, values = median_times_and_values(runs, min(repeat, MAX_REPEAT))
    errors = [_relmse(v, ref) for v in values]
    curve = ErrorCurve(times[:-1], errors[:-1])
    steps = ", ".join(f"{n} paths {t:.2f} s relMSE {e:.3g}" for n, t, e in zip(sizes.ladder, times, errors))
    bias = float(np.mean(values[-1]) / np.mean(ref) - 1)
    what = (
        f"radiance cache at {len(points)} sensors ({sizes.step:g} m grid, {INDIRECT_SCENE}), "
        f"{sizes.resolution}x{sizes.resolution} texels a cache point, bound {settings.bound:g}: {times[-1]:.2f} s, "
        f"relMSE {errors[-1]:.3g}, mean {bias:+.2%} against the reference"
    )
    baseline = f"sensor paths at equal relMSE ({steps}); reference {sizes.reference_spp} paths a sensor"
    ratio = curve.seconds_for(errors[-1]) / times[-1]
    return [Record("lighting.indirect.vs_path_equal_error", what, baseline, ratio, times[-1], "s")]


def bench_lighting(repeat: int, quick: bool) -> list[Record]:
    """The `lighting` group (GROUPS in bench/run.py)."""
    return _direct_records(repeat, quick) + _indirect_record(repeat, quick)
