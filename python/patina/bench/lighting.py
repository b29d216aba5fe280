"""`patina bench --only lighting` (issue 32): the lighting calculations' speed.

`lighting.direct.sensors_per_s.w<N>`: the exact direct illuminance (patina.lighting.direct, the
native kernel of render/lighting/direct_illuminance.h) of 10^5 horizontal sensors (`--quick`:
4096) under 20 luminaires (the bundled downlight IES and street-light EULUMDAT files alternating
on a 5 x 4 grid, 3.5 to 5 m up) over a 40 x 30 m floor with spheres and balls casting shadows:
one candela lookup and one shadow ray per luminaire per sensor (packets through the scene's
BVH, built on the warm-up run), one thread, at width N against width 1; value the sensors per
second at width N.

`lighting.indirect.vs_path_equal_error`: the sensor kernel (`_core.sensor_illuminance`) has no
radiance-cache path (its interreflections are path-traced sensor paths only), so the record
measures what can be: the bundled office's camera image (materials/scenes/office-en12464.json:
the floor, desks and walls the office project's grids lie on) rendered by `cache` against
`path` at equal relMSE, as `cache.<scene>.biased_vs_path` does (bench/cache.py, with its sizes),
on every core.
"""

from __future__ import annotations

import functools
import os
import sys

import numpy as np

from patina.bench.cache import FULL, MAX_REPEAT, QUICK
from patina.bench.convergence import (
    ErrorCurve,
    Run,
    integrator_missing,
    median_relmse,
    reference,
    sized,
    timed_renders,
)
from patina.bench.records import Record, median_times, simd_widths
from patina.bundled import materials_path
from patina.lighting.direct import PlacedSource, direct_illuminance
from patina.lighting.sensors import make_sensors
from patina.render.illuminance import ray_offset
from patina.render.prepare import PreparedScene
from patina.scene.reading import load_scene, parse_scene, with_overrides

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


def _indirect_record(repeat: int, quick: bool) -> list[Record]:
    sizes = QUICK if quick else FULL  # the cache group's sizes and repeats
    scene_file = materials_path("scenes", f"{INDIRECT_SCENE}.json")
    scene = sized(load_scene(scene_file), sizes.width)
    why = integrator_missing(scene, "cache")
    if why is not None:
        print(f"patina bench: lighting.indirect.vs_path_equal_error skipped: {why}", file=sys.stderr)
        return []
    threads = os.cpu_count() or 1
    ref = reference(scene_file, scene, sizes.reference_spp, threads)
    path_scene = with_overrides(scene, integrator="path")
    path_prep = PreparedScene(path_scene)
    runs = [Run(with_overrides(path_scene, spp=n), path_prep, threads) for n in sizes.ladder]
    cache_scene = with_overrides(scene, integrator="cache", spp=sizes.candidate_spp)
    runs.append(Run(cache_scene, PreparedScene(cache_scene), threads))
    times, images = timed_renders(runs, min(repeat, MAX_REPEAT))
    errors = [median_relmse(imgs, ref.image, ref.error) for imgs in images]
    curve = ErrorCurve(times[:-1], errors[:-1])
    steps = ", ".join(f"{s} spp {t:.2f} s relMSE {e:.3g}" for s, t, e in zip(sizes.ladder, times, errors))
    size = f"{scene.camera.width}x{scene.camera.height}"
    what = (
        f"cache, {INDIRECT_SCENE} {size} camera image (no cache sensor kernel), {sizes.candidate_spp} spp, "
        f"{threads} threads: {times[-1]:.2f} s, relMSE {errors[-1]:.3g}"
    )
    baseline = f"path at equal relMSE ({steps}); reference {sizes.reference_spp} spp of path"
    ratio = curve.seconds_for(errors[-1]) / times[-1]
    return [Record("lighting.indirect.vs_path_equal_error", what, baseline, ratio, times[-1], "s")]


def bench_lighting(repeat: int, quick: bool) -> list[Record]:
    """The `lighting` group (GROUPS in bench/run.py)."""
    return _direct_records(repeat, quick) + _indirect_record(repeat, quick)
