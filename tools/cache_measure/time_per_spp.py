"""`cache`'s time per spp, relMSE, bias and ratio against path's ladder (8 to 512 spp, same
process) on the bundled cache scenes, with the bench's own functions (bench/convergence.py),
64 pixels wide, 2 threads, median of 3 (docs/radiance-cache.md).
Run from the checkout: python tools/cache_measure/time_per_spp.py LABEL [spp ...]
(SCENES=cache-room,... to choose the scenes)."""

import os
import sys

from patina.bench.cache import FULL
from patina.bench.convergence import ErrorCurve, Run, reference, relmse, sized, timed_renders
from patina.bundled import materials_path
from patina.render.run import PreparedScene
from patina.scene.reading import load_scene, with_overrides

label = sys.argv[1]
spps = [int(a) for a in sys.argv[2:]] or [16, 64]
ladder = (8, 32, 128, 512)
scenes = os.environ.get("SCENES", "cache-room,cache-studio,cache-ies-interior").split(",")
for name in scenes:
    f = materials_path("scenes", f"{name}.json")
    scene = sized(load_scene(f), FULL.width)
    ref = reference(f, scene, FULL.reference_spp, 2)
    cands = [
        Run(
            with_overrides(scene, integrator="cache", spp=n),
            PreparedScene(with_overrides(scene, integrator="cache", spp=n)),
            2,
        )
        for n in spps
    ]
    ps = with_overrides(scene, integrator="path")
    pp = PreparedScene(ps)
    lad = [Run(with_overrides(ps, spp=n), pp, 2) for n in ladder]
    times, images = timed_renders(lad + cands, 3)
    errs = [relmse(i, ref.image, ref.error) for i in images]
    curve = ErrorCurve(times[: len(ladder)], errs[: len(ladder)])
    load = open("/proc/loadavg").read().split()[:3]
    for k, n in enumerate(spps):
        i = len(ladder) + k
        bias = 100 * (float(images[i].mean()) / float(ref.image.mean()) - 1)
        print(
            f"{label} {name} cache {n} spp: {times[i]:.3f} s ({times[i] / n * 1000:.1f} ms/spp) relMSE {errs[i]:.4g} "
            f"bias {bias:+.2f}% vs_path {curve.seconds_for(errs[i]) / times[i]:.2f}  load {' '.join(load)}",
            flush=True,
        )
    print(
        f"{label} {name} path ladder " + ", ".join(f"{s}:{t:.2f}s/{e:.3g}" for s, t, e in zip(ladder, times, errs)),
        flush=True,
    )
