"""Where `path`'s and `cache-guided`'s error comes from: each pixel's 16 spp estimate split into
the direct light at the first vertex (its light samples and the emitters its first bounce hits,
camera-seen emission included), the direct light at the second vertex (one bounce of indirect
light) and the rest (the light after the second bounce), and each part's share of the bench's
relMSE (docs/radiance-cache.md, "Where the variance is").

The split is exact per sample: a render cut to `max_depth` 2 (or 3) with the same seed draws
the same numbers at the vertices it keeps (render/samplers/sample_numbers.h: they are functions of stream,
index, bounce and use), so it is the full render's first part (first two parts) and the
differences are the others. For `cache-guided` the cut renders sample the guide trained on full
paths (the options' `cache.train_max_depth`), so their vertices are the full
render's. The error e = x - r splits as the parts' errors against the same split of the
reference (`path` cut at CUT_SPP spp, and the bench's reference); with the bench's per-pixel
weight w = 1 / (r^2 + eps) (both images over r's mean) the relMSE is the sum of each part's
mean(w e_p^2) and the cross terms, over the pixels the bench keeps (its top 0.1 % of the full
error discarded). A first-bounce guide draws the first bounce's direction: it changes the
direct part only through the MIS weights and lowers the others only as far as their error
comes from where the first bounce went, not from the sampling at later vertices.
Printed per scene and integrator: the medians over the seeds of the relMSE, of each part's
term (its share) and of the cross terms' sum, and each seed's terms.
Run from the checkout: python tools/cache_measure/variance_split.py (SCENES=cache-room,...,
SEEDS=4, CUT_SPP=1024; keyword arguments of with_overrides for cache-guided as a JSON
argument, e.g. '{"cache_train_passes": 2}')."""

import dataclasses
import itertools
import json
import os
import statistics
import sys

import numpy as np
from path_ladder import path_ladder

from patina.bench.cache import FULL
from patina.bench.convergence import DISCARD_FRACTION, RELMSE_EPSILON, reference
from patina.render.run import PreparedScene, job_settings, new_job, path_depth
from patina.scene.reading import with_overrides

CUT_DEPTHS = (2, 3)  # Mitsuba's count: direct light at the first vertex; and at the second


def cut(scene, depth):
    return dataclasses.replace(scene, render=dataclasses.replace(scene.render, max_depth=depth))


def rendered(scene, prep, train_max_depth=0):
    """The scene's rgb on 2 threads, its guide (cache-guided) trained on paths of
    train_max_depth (in segments, as render.max_depth; 0: the render's)."""
    settings = job_settings(scene, None, None, None, None)
    settings.cache.train_max_depth = train_max_depth
    job = new_job(prep, settings, threads=2)
    job.start()
    job.wait()
    return np.asarray(job.resolve().rgb, np.float64)


def split_terms(parts, ref_parts, ref):
    """(relMSE, each part's own term..., the cross terms' sum) of one render as the bench
    measures it: parts and ref_parts the estimate's and the references' parts (summing to the
    full estimate and to ref)."""
    scale = float(ref.mean())
    w = 1.0 / ((ref / scale) ** 2 + RELMSE_EPSILON)
    errors = [(p - r) / scale for p, r in zip(parts, ref_parts)]
    total = w * sum(errors) ** 2
    own = [w * e**2 for e in errors]

    def per_pixel(a):  # RGB averaged, as pixel_relmse
        return a.mean(axis=-1).ravel()

    keep = np.argsort(per_pixel(total))[: per_pixel(total).size - int(per_pixel(total).size * DISCARD_FRACTION)]
    terms = [float(per_pixel(t)[keep].mean()) for t in [total, *own]]
    return (*terms, terms[0] - sum(terms[1:]))


def main():
    guided = json.loads(sys.argv[1]) if len(sys.argv) > 1 else {}
    seeds = int(os.environ.get("SEEDS", "4"))
    cut_spp = int(os.environ.get("CUT_SPP", "1024"))
    scenes = os.environ.get("SCENES", "cache-room,cache-studio,cache-ies-interior").split(",")
    names = ["direct", "1-bounce", "later"]
    for name in scenes:
        f, scene, ref, _ = path_ladder(name)
        path_scene = with_overrides(scene, integrator="path")
        cut_refs = [reference(f, cut(path_scene, d), cut_spp, 2) for d in CUT_DEPTHS]
        levels = [r.image for r in cut_refs] + [ref.image]
        ref_parts = [levels[0]] + [b - a for a, b in itertools.pairwise(levels)]
        errs = ", ".join(f"{r.error:.3g}" for r in [*cut_refs, ref])
        print(f"{name}: the references' own errors (cut at {CUT_DEPTHS}, full) {errs}")
        integrators = (("path", {"integrator": "path"}), ("cache-guided", {"integrator": "cache-guided", **guided}))
        for label, over in integrators:
            full_scene = with_overrides(scene, spp=FULL.candidate_spp, **over)
            scenes_cut = [cut(full_scene, d) for d in CUT_DEPTHS] + [full_scene]
            preps = [PreparedScene(s) for s in scenes_cut]
            terms = []
            for k in range(seeds):
                seed = scene.render.seed + k
                images = [
                    rendered(with_overrides(s, seed=seed), p, path_depth(full_scene)) for s, p in zip(scenes_cut, preps)
                ]
                parts = [images[0]] + [b - a for a, b in itertools.pairwise(images)]
                if min(float(p.min()) for p in parts) < -1e-3 * float(images[-1].max()):
                    raise SystemExit(f"{name} {label} seed {seed}: a negative part, the split is not exact")
                terms.append(split_terms(parts, ref_parts, ref.image))
            med = [statistics.median(t[j] for t in terms) for j in range(len(terms[0]))]
            shares = ", ".join(f"{n} {v:.4g} ({v / med[0]:.0%})" for n, v in zip(names, med[1:-1]))
            per_seed = " ".join("/".join(f"{v:.3g}" for v in t[1:-1]) for t in terms)
            print(f"  {label:12s} relMSE {med[0]:.4g}: {shares}, cross {med[-1]:+.3g}; per seed {per_seed}", flush=True)


main()
