"""Error at equal samples on the gold sphere, Patina's samplers against Mitsuba 3's, and how
much of it each of Mitsuba's light and BRDF sampling carries (docs/performance.md, "Error per
sample on the gold sphere").

Each renderer is measured against its own converged image (two halves of REF_SPP independent
samples; a quarter of their mean squared difference, the reference's own error, is subtracted),
so neither side's bias against the other (Patina's height-correlated Smith term: +0.28 % on the
image mean) counts. relMSE = mean squared error / the reference's mean squared, the mean of SEEDS
renders, all threads, 128 x 96 (conductor-sphere.json, direct lighting, MIS on both sides).
Mitsuba's `direct` integrator also runs with only its light samples (emitter_samples 1,
bsdf_samples 0) or only its BRDF samples, which Patina has no switch for.
Mitsuba's multijitter and ldsampler round the sample count up (to a x b, to a power of 4): the
count rendered is given in brackets where it differs.
Usage: .venv/bin/python tools/vs_mitsuba_samplers.py [SPP ...]   (default 64 128 256 512)
"""

from __future__ import annotations

import os
import sys

import numpy as np

from patina.bench import render as R
from patina.render.run import PreparedScene
from patina.scene.reading import load_scene, with_overrides

REF_SPP, SEEDS = 16384, 4


def rel_mse(render_at, spp: int, reference: np.ndarray, reference_mse: float) -> float:
    errors = [float(((render_at(spp, 100 + s) - reference) ** 2).mean()) - reference_mse for s in range(SEEDS)]
    return float(np.mean(errors)) / float(reference.mean()) ** 2


def mitsuba_renderer(scene, sampler: str, emitter_samples: int = 1, bsdf_samples: int = 1):
    """The bench's llvm_ad_rgb renderer of the scene with Mitsuba's `direct` integrator."""
    integrator = {"type": "direct", "emitter_samples": emitter_samples, "bsdf_samples": bsdf_samples}
    return R._mitsuba_renderer(scene, "llvm_ad_rgb", os.cpu_count() or 1, sampler=sampler, integrator=integrator)


def rendered_spp(sampler: str | None, spp: int) -> int:
    """The count Mitsuba's `sampler` renders for `spp` (multijitter and ldsampler round it up);
    Patina's samplers (None) render it as asked."""
    if sampler is None:
        return spp
    import mitsuba as mi

    return mi.load_dict({"type": sampler, "sample_count": spp}).sample_count()


def main() -> None:
    levels = [int(a) for a in sys.argv[1:]] or [64, 128, 256, 512]
    threads = os.cpu_count() or 1
    scene = with_overrides(load_scene(R._scene_path("conductor-sphere")), width=128, height=96, seed=0)
    prep = PreparedScene(scene)

    def patina(sampler: str):
        return lambda spp, seed: R._render(prep, scene, 0, threads, spp, seed=seed, sampler=sampler)

    patina_ref = R._own_reference(patina("independent"), REF_SPP)
    mitsuba_ref = R._own_reference(mitsuba_renderer(scene, "independent"), REF_SPP)
    # name: (renderer, its own reference, the Mitsuba sampler that may round the count)
    runs = {
        "Patina sobol": (patina("sobol"), patina_ref, None),
        "Patina independent": (patina("independent"), patina_ref, None),
        "Mitsuba multijitter": (mitsuba_renderer(scene, "multijitter"), mitsuba_ref, "multijitter"),
        "Mitsuba ldsampler": (mitsuba_renderer(scene, "ldsampler"), mitsuba_ref, "ldsampler"),
        "Mitsuba independent": (mitsuba_renderer(scene, "independent"), mitsuba_ref, "independent"),
        "Mitsuba multijitter, light samples only": (
            mitsuba_renderer(scene, "multijitter", 1, 0),
            mitsuba_ref,
            "multijitter",
        ),
        "Mitsuba multijitter, BRDF samples only": (
            mitsuba_renderer(scene, "multijitter", 0, 1),
            mitsuba_ref,
            "multijitter",
        ),
    }
    print("load", os.getloadavg(), "references' own relMSE", patina_ref[1] / patina_ref[0].mean() ** 2,
          mitsuba_ref[1] / mitsuba_ref[0].mean() ** 2)  # fmt: skip
    print("| sampler | " + " | ".join(f"{n} spp" for n in levels) + " |")
    for name, (render_at, (reference, reference_mse), sampler) in runs.items():
        cells = []
        for n in levels:
            error = rel_mse(render_at, n, reference, reference_mse)
            actual = rendered_spp(sampler, n)
            cells.append(f"{error:.2e}" + (f" ({actual})" if actual != n else ""))
        print(f"| {name} | " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
