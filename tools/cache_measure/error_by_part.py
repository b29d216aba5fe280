"""Where an integrator's error lies on cache-car (docs/radiance-cache.md, "The car"): per
configuration, the bench's relMSE against its kept reference at the bench's size (192 pixels
wide), and the terms of the floor's pixels and the car's (the sky has none: the camera sees
the environment exactly), medians over seeds 1-3 on 2 threads, with one thread's CPU seconds
in work items (`RenderJob.stage_times()`, stage_clock "cpu": robust to the other sessions'
load). Run from the checkout: python tools/cache_measure/error_by_part.py
integrator=cache,spp=16,cache_light_samples=4 integrator=path,spp=32 ... (with_overrides
keywords, one configuration an argument; SCENE=cache-car)."""

import os
import statistics
import sys

import numpy as np
from configuration_runs import cpu_seconds, overrides

from patina.bench.cache import FULL
from patina.bench.convergence import DISCARD_FRACTION, pixel_relmse, reference, relmse, sized
from patina.bundled import materials_path
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides

FLOOR_ALBEDO = 0.8  # cache-car.json's floor: its pixels are those of this albedo


def measure(scene, ref) -> tuple[float, float, float, float]:
    result = render(scene, threads=2)
    errors = pixel_relmse(result.rgb, ref.image).reshape(result.depth.shape)
    errors = np.minimum(errors, np.quantile(errors, 1 - DISCARD_FRACTION))
    floor = np.isfinite(result.depth) & (np.abs(result.albedo.mean(axis=2) - FLOOR_ALBEDO) < 0.01)
    car = np.isfinite(result.depth) & ~floor
    parts = [errors[m].sum() / errors.size for m in (floor, car)]
    return relmse(result.rgb, ref.image, ref.error), *parts, cpu_seconds(scene)


name = os.environ.get("SCENE", "cache-car")
scene_file = materials_path("scenes", f"{name}.json")
base = sized(load_scene(scene_file), FULL.width)
ref = reference(scene_file, base, FULL.reference_spp, 2)
for config in sys.argv[1:]:
    runs = [measure(with_overrides(base, seed=seed, **overrides(config)), ref) for seed in (1, 2, 3)]
    total, floor, car, cpu = (statistics.median(r[k] for r in runs) for k in range(4))
    print(f"{name} {config}: relMSE {total:.4g} (floor {floor:.4g}, car {car:.4g}), CPU {cpu:.3f} s", flush=True)
