"""`cache`'s biased_vs_path per setting, in one thread's CPU seconds (robust to the shared
machine's load): on a bundled cache scene at the bench's size (bench/cache.py FULL: 192 pixels
wide), `path`'s curve at the bench's ladder (8, 32, 128 spp) and `cache` at 16 spp under each
configuration, the relMSE the median over seeds 0-3 against the bench's kept reference, the
CPU time the median over REPEAT one-thread renders (`RenderJob.stage_times()`, stage_clock
"cpu"). docs/radiance-cache.md, "The room and the car: where the time and the error go". Run from the
checkout: SCENE=cache-room python tools/cache_measure/settings_sweep.py defaults
cache_block=16 cache_block=16,cache_error=1.0 (with_overrides keywords, one configuration
an argument; "defaults" for the scene's own)."""

import os
import statistics
import sys

from configuration_runs import cpu_seconds, overrides

from patina.bench.cache import FULL
from patina.bench.convergence import ErrorCurve, median_relmse, reference, sized
from patina.bundled import materials_path
from patina.render.run import PreparedScene, render
from patina.scene.reading import load_scene, with_overrides

SEEDS = (0, 1, 2, 3)
REPEAT = int(os.environ.get("REPEAT", "3"))


def median_error(scene, ref) -> float:
    prep = PreparedScene(scene)
    images = [render(with_overrides(scene, seed=s), threads=2, prepared=prep).rgb for s in SEEDS]
    return median_relmse(images, ref.image, ref.error)


def interleaved_seconds(scenes: list) -> list[float]:
    """Each scene's median CPU seconds over REPEAT rounds, every round timing all of them in
    turn, so a burst of load from other work weighs on all alike."""
    rounds = [[cpu_seconds(s) for s in scenes] for _ in range(REPEAT)]
    return [statistics.median(r[i] for r in rounds) for i in range(len(scenes))]


name = os.environ.get("SCENE", "cache-room")
scene_file = materials_path("scenes", f"{name}.json")
base = sized(load_scene(scene_file), FULL.width)
ref = reference(scene_file, base, FULL.reference_spp, 2)
path_scenes = [with_overrides(base, integrator="path", spp=n) for n in FULL.ladder]
names = sys.argv[1:]
cache_scenes = [with_overrides(base, integrator="cache", spp=FULL.candidate_spp, **overrides(t)) for t in names]
errors = [median_error(s, ref) for s in path_scenes + cache_scenes]
seconds = interleaved_seconds(path_scenes + cache_scenes)
n = len(path_scenes)
curve = ErrorCurve(seconds[:n], errors[:n])
steps = ", ".join(f"{k} spp relMSE {e:.4g} CPU {t:.3f} s" for k, e, t in zip(FULL.ladder, errors, seconds))
print(f"{name} path: {steps}", flush=True)
for text, error, t in zip(names, errors[n:], seconds[n:]):
    print(f"{name} {text}: relMSE {error:.4g}, CPU {t:.3f} s, biased_vs_path {curve.seconds_for(error) / t:.2f}")
