"""`cache-guided` variants against path's ladder (8, 32, 128 spp) in the same process, as the
bench's `cache.<scene>.guided_vs_path` measures them (bench/cache.py FULL: 192 pixels wide, 16 spp,
2 threads, the converged reference kept by the bench, errors the median over the seeds
0 .. REPEAT): per variant its median time, its relMSE, the ratio (docs/radiance-cache.md,
"The trained guide"), its image mean over the reference's (the mean over the seeds: unbiased
estimators give 1 within the seeds' scatter) and its time a sample a pixel.
Run from the checkout: python tools/cache_measure/guided_variants.py '[{"cache_train_passes": 0}, {}]'
(each variant: keyword arguments of with_overrides, `spp` among them to replace the bench's 16;
SCENES=cache-room,... and REPEAT=3; INTEGRATOR=cache for `cache`'s variants, its ratio the
bench's `biased_vs_path`)."""

import json
import os
import sys

from path_ladder import path_ladder

from patina.bench.cache import FULL
from patina.bench.convergence import ErrorCurve, Run, median_relmse, timed_renders
from patina.render.run import PreparedScene
from patina.scene.reading import with_overrides

variants = json.loads(sys.argv[1]) if len(sys.argv) > 1 else [{}]
repeat = int(os.environ.get("REPEAT", "3"))
integrator = os.environ.get("INTEGRATOR", "cache-guided")
key = "guided_vs_path" if integrator == "cache-guided" else "biased_vs_path"
scenes = os.environ.get("SCENES", "cache-room,cache-studio,cache-ies-interior").split(",")
for name in scenes:
    f, scene, ref, ladder = path_ladder(name)
    candidates = []
    for v in variants:
        c = with_overrides(scene, integrator=integrator, **{"spp": FULL.candidate_spp, **v})
        candidates.append(Run(c, PreparedScene(c), 2))
    times, images = timed_renders(ladder + candidates, repeat)
    errors = [median_relmse(i, ref.image, ref.error) for i in images]
    n = len(FULL.ladder)
    curve = ErrorCurve(times[:n], errors[:n])
    print(name, "path", " ".join(f"{s} spp {t:.3f} s {e:.4g}" for s, t, e in zip(FULL.ladder, times, errors)))
    path_per_spp = times[n - 1] / FULL.ladder[-1]
    for v, c, t, e, i in zip(variants, candidates, times[n:], errors[n:], images[n:]):
        mean = sum(float(x.mean()) for x in i) / len(i) / float(ref.image.mean())
        per_spp = t / c.scene.render.spp
        print(
            f"  {v}: {t:.3f} s, relMSE {e:.4g}, {key} {curve.seconds_for(e) / t:.2f}, mean / reference {mean:.4f},"
            f" {1000 * per_spp:.2f} ms a spp ({per_spp / path_per_spp:.2f} x path's)",
            flush=True,
        )
