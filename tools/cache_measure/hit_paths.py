"""`cache` with several values of cache.hit_paths against path's ladder in the same process,
at the bench's size (FULL: 192 pixels wide, 16 spp, 2 threads; the errors the median over 4 seeds as the
bench's), the bias as the bench's record measures it (bench/cache.py, bias_over_seeds: 16 seeds,
32 pixels wide) and the same at 96 pixels, the bench's size until issue 31 (docs/radiance-cache.md, "Bias").
Run from the checkout: python tools/cache_measure/hit_paths.py LABEL K,K,... [scene,...]"""

import sys

from path_ladder import path_ladder

from patina.bench.cache import BIAS_SIZES, FULL, bias_over_seeds
from patina.bench.convergence import ErrorCurve, Run, Sizes, median_relmse, timed_renders
from patina.render.run import PreparedScene
from patina.scene.reading import with_overrides

label = sys.argv[1]
values = [int(x) for x in sys.argv[2].split(",")]
scenes = sys.argv[3].split(",") if len(sys.argv) > 3 else ["cache-room", "cache-studio", "cache-ies-interior"]
for name in scenes:
    f, scene, ref, ladder = path_ladder(name)
    times, images = timed_renders(ladder, 3)
    curve = ErrorCurve(times, [median_relmse(i, ref.image, ref.error) for i in images])
    for s in values:
        cand = with_overrides(scene, integrator="cache", spp=FULL.candidate_spp, cache_hit_paths=s)
        (t,), (imgs,) = timed_renders([Run(cand, PreparedScene(cand), 2)], 3)
        e = median_relmse(imgs, ref.image, ref.error)
        ratios, _ = bias_over_seeds(f, with_overrides(scene, cache_hit_paths=s), "cache", BIAS_SIZES, 2)
        bias, se, seeds = 100 * (ratios.mean() - 1), 100 * ratios.std(ddof=1) / len(ratios) ** 0.5, len(ratios)
        full, _ = bias_over_seeds(f, with_overrides(scene, cache_hit_paths=s), "cache", Sizes(96, 2048, (), 16), 2)
        bias96, sd96 = 100 * (full.mean() - 1), 100 * full.std(ddof=1)
        load = open("/proc/loadavg").read().split()[0]
        print(
            f"{label} {name} hit_paths {s}: {t:.3f} s relMSE {e:.4g} vs_path {curve.seconds_for(e) / t:.2f} "
            f"bias {bias:+.2f} +- {se:.2f} % ({seeds} seeds); at 96 px {bias96:+.2f} +- {sd96 / 4:.2f} % "
            f"(per seed sd {sd96:.1f} %, max {100 * (full.max() - 1):+.1f} %)  load {load}",
            flush=True,
        )
