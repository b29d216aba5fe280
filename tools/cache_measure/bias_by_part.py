"""`cache`'s relative bias against the bench's kept reference per seed, and for the first seed
the share of the deficit held by the floor, the ceiling and the walls (by the normal AOV),
64 pixels wide, 2 threads (docs/radiance-cache.md, "Where the room's bias comes from").
Run from the checkout: python tools/cache_measure/bias_by_part.py LABEL SPP SEED,SEED,...
[scene=NAME] [cache_error=0.15 ...] (with_overrides keywords)."""

import sys

import numpy as np

from patina.bench.cache import FULL
from patina.bench.convergence import reference, sized
from patina.bundled import materials_path
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides

label, spp, seeds = sys.argv[1], int(sys.argv[2]), [int(x) for x in sys.argv[3].split(",")]
over = dict(a.split("=") for a in sys.argv[4:])
name = over.pop("scene", "cache-room")
f = materials_path("scenes", f"{name}.json")
scene = sized(load_scene(f), FULL.width)
ref = reference(f, scene, FULL.reference_spp, 2)
kw = {k: (float(v) if "." in v else int(v)) for k, v in over.items()}
bs = []
for seed in seeds:
    s = with_overrides(scene, integrator="cache", spp=spp, seed=seed, **kw)
    r = render(s, threads=2)
    img = r.rgb
    bs.append(100 * (img.mean() / ref.image.mean() - 1))
    if seed == seeds[0]:
        n = r.normal
        ref_mean = ref.image.mean(axis=2)
        d = (img - ref.image).mean(axis=2)
        tot = (img - ref.image).mean() * img.shape[0] * img.shape[1]
        parts = {
            "floor(n.y>.7)": n[..., 1] > 0.7,
            "ceiling(n.y<-.7)": n[..., 1] < -0.7,
            "walls": np.abs(n[..., 1]) <= 0.7,
        }
        print(
            label,
            "share of the bias:",
            " ".join(
                f"{k} {d[m].sum() / tot * 100 if tot else 0:.0f}% (rel {d[m].mean() / ref_mean[m].mean() * 100:+.1f}%)"
                for k, m in parts.items()
            ),
        )
print(label, name, spp, kw, "bias per seed", " ".join(f"{b:+.2f}" for b in bs), f"mean {np.mean(bs):+.2f}", flush=True)
