"""The `lights` benchmark group: light sampling with shadow rays for a batch of shading
points (sensors on a floor under the light, one light sample and one shadow ray each per
round), at SIMD widths 4 and 8 against width 1, for a goniometric light (the bundled street
light's IES table), an area light (a disc of 128 triangles) and an environment map (the
studio map). One thread, one prepared scene; value in Msamples/s (light samples with their
shadow rays)."""

from __future__ import annotations

import functools
import os

import numpy as np

from patina.bench.records import Record, median_times, simd_widths
from patina.bundled import materials_path
from patina.native import _core
from patina.render.run import PreparedScene
from patina.scene.reading import parse_scene


def _scene(light: dict | None, environment: dict | None) -> object:
    obj = {
        "version": 1,
        "camera": {"position": [0, 5, 5], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "materials": {"m": {"type": "lambert", "albedo": 0.5}},
        "shapes": [
            {"type": "plane", "material": "m", "size": [40, 40]},
            {"type": "ball", "material": "m", "transform": {"translate": [1, 0, 1]}},  # something to cast shadows
        ],
        "lights": [light] if light else [],
    }
    if environment:
        obj["environment"] = environment
    return parse_scene(obj, os.path.join(materials_path(), "bench.json"))


def bench_lights(repeat: int, quick: bool) -> list[Record]:
    mat = materials_path()
    cases = {
        "goniometric": (
            {"type": "luminaire", "file": os.path.join(mat, "luminaires", "streetlight.ies"), "position": [-1, 6, 0]},
            None,
        ),
        "area": ({"type": "disk", "center": [0, 3, 0], "normal": [0, -1, 0], "radius": 0.5, "radiance": 5}, None),
        "environment": (None, {"type": "map", "file": os.path.join(mat, "env", "studio.exr")}),
    }
    side = 64 if quick else 256
    x = np.linspace(-6, 6, side, dtype=np.float32)
    xx, zz = np.meshgrid(x, x)
    points = np.ascontiguousarray(np.stack([xx.ravel(), np.zeros(xx.size, np.float32), zz.ravel()], 1))
    normals = np.ascontiguousarray(np.tile(np.array([0, 1, 0], np.float32), (len(points), 1)))
    samples = 2 if quick else 8
    records = []
    for name, (light, env) in cases.items():
        prepared = PreparedScene(_scene(light, env))
        run = functools.partial(_core.sensor_illuminance, prepared.core, points, normals, samples, 0)
        count = len(points) * samples
        for w in simd_widths():
            t1, tw = median_times([functools.partial(run, 1, 1), functools.partial(run, w, 1)], repeat)
            records.append(
                Record(
                    f"lights.sample.{name}.w{w}",
                    f"{count} light samples with shadow rays ({name}), width {w}, 1 thread",
                    "the same at width 1",
                    t1 / tw,
                    count / tw / 1e6,
                    "Msamples/s",
                )
            )
    return records
