"""Where a cache point's heavy tail lies (docs/radiance-cache.md, "Bias"): one cache point of
the room built at A for many seeds (patina.native._core.cache_probe), its hemisphere's
irradiance-like sum (sum of L cos x texel solid angle) per seed, and the texels that carry
the largest values: their share of the sum, what they hit (the floor, judged by the hit's
height), and how the tail changes with the cache's own path depth.
Run from the checkout: python tools/cache_measure/texel_tail.py [SEEDS] [max_depth ...] (in segments,
as a scene file's render.max_depth)
(A on the ceiling facing down, unless A=x,y,z N=x,y,z are given in the environment)."""

import os
import sys

import numpy as np

from patina.bundled import materials_path
from patina.native import _core
from patina.render.prepare import PreparedScene
from patina.scene.reading import load_scene

seeds = int(sys.argv[1]) if len(sys.argv) > 1 else 64
depths = [int(a) for a in sys.argv[2:]] or [4, 9]
a = [float(x) for x in os.environ.get("A", "0.0,2.59,0.0").split(",")]
n = [float(x) for x in os.environ.get("N", "0,-1,0").split(",")]
scene = load_scene(materials_path("scenes", os.environ.get("SCENE", "cache-room") + ".json"))
prep = PreparedScene(scene)
R = 24
omega = 2 * np.pi / (R * R)
for depth in depths:
    sums, top_share, top_floor, tops = [], [], [], []
    for seed in range(seeds):
        p = _core.cache_probe(prep.core, a, n, a, n, resolution=R, max_depth=depth, seed=seed)
        rad = np.asarray(p.a_radiance).mean(axis=2)  # (R, R)
        u = (np.arange(R) + 0.5) / R
        # the texel centres' cos theta (z = 1 - r^2 with r the concentric map's radius)
        uu, vv = np.meshgrid(2 * u - 1, 2 * u - 1)
        z = 1 - np.maximum(np.abs(uu), np.abs(vv)) ** 2
        contrib = rad * z * omega
        s = contrib.sum()
        sums.append(s)
        k = np.argmax(contrib)
        tops.append(contrib.flat[k])
        top_share.append(contrib.flat[k] / s if s > 0 else 0)
        dist = np.asarray(p.a_dist).flat[k]
        # A faces the floor: a hit at distance d along cos z lies at height a_y - d z
        top_floor.append(bool(np.isfinite(dist) and abs(a[1] - dist * z.flat[k]) < 0.05))
    sums = np.array(sums)
    mean, se = sums.mean(), sums.std(ddof=1) / np.sqrt(seeds)
    order = np.argsort(sums)[::-1]
    print(
        f"max_depth {depth}: hemisphere sum mean {mean:.4g} +- {se:.2g} (sd/mean {sums.std() / mean:.2f}), "
        f"median {np.median(sums):.4g}, max {sums.max():.4g} (seed {order[0]}); "
        f"largest texel's share: median {np.median(top_share):.2f}, max {max(top_share):.2f}; "
        f"largest texel on the floor in {np.mean(top_floor) * 100:.0f} % of seeds; "
        f"top 3 seeds' share of the total {sums[order[:3]].sum() / sums.sum():.2f}",
        flush=True,
    )
