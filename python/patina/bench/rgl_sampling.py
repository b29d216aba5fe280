"""`render.rgl.sampling_vs_cosine` (the `rgl` group): what the RGL material's own importance
sampling (its luminance and VNDF warps, render/materials/rgl_material.h) is worth in a render.

A glossy plastic (GGX alpha 0.15 over a dark base, Schlick F0 0.6) written as an RGL file by
the test-suite writer, on the preview sphere under the bundled studio map, path traced at
32 x 24 (quick: 16 x 12). Reference: the file's own sampling at 4096 spp (quick: 512) as
two halves of different seeds, their mean the reference and a quarter of their mean squared
difference its own MSE, subtracted from every measured MSE. The target is the MSE the file's
own sampling reaches at 64 spp; cosine sampling renders at 64, 256, 1024, ... spp until it
reaches it, and its spp to the target is interpolated between the last two levels by a power
law. Every MSE is the median of 3 renders of different seeds. ratio = cosine's spp / 64.
"""

from __future__ import annotations

import os
import statistics
import tempfile

import numpy as np

from patina.bench.records import Record
from patina.bench.render import _spp_to_target
from patina.bundled import studio_environment
from patina.render.run import render
from patina.scene.preview import preview_scene_dict
from patina.scene.reading import parse_scene
from patina.synthetic.analytic import plastic
from patina.table.formats.rgl_writer import write_rgl

OWN_SPP = 64
RUNS = 3  # renders of different seeds a level; their median MSE


def glossy_rgl_file(folder: str) -> str:
    path = os.path.join(folder, "glossy.bsdf")
    write_rgl(path, plastic(diffuse=(0.05, 0.05, 0.05), specular=0.6, roughness=0.15), description="bench glossy")
    return path


def sampling_vs_cosine_record(quick: bool) -> Record:
    width, height, ref_spp = (16, 12, 512) if quick else (32, 24, 4096)
    with tempfile.TemporaryDirectory() as folder:
        file = glossy_rgl_file(folder)

        def render_at(sampling: str, spp: int, seed: int) -> np.ndarray:
            obj = preview_scene_dict(file, studio_environment(), "sphere", coat=False)
            obj["materials"]["material"]["sampling"] = sampling
            obj["camera"].update(width=width, height=height)
            obj["render"].update(spp=spp, seed=seed)
            return np.asarray(render(parse_scene(obj, os.path.join(folder, "bench.json"))).rgb, np.float64)

        a, b = render_at("file", ref_spp // 2, 1001), render_at("file", ref_spp // 2, 1002)
        reference, reference_mse = (a + b) / 2, float(((a - b) ** 2).mean()) / 4

        def mse_at(sampling: str, spp: int) -> float:
            errors = [float(((render_at(sampling, spp, seed) - reference) ** 2).mean()) for seed in range(RUNS)]
            return max(statistics.median(errors) - reference_mse, 1e-30)

        target = mse_at("file", OWN_SPP)
        spp, levels = _spp_to_target(lambda n: mse_at("cosine", n), target, OWN_SPP, 4 * ref_spp)
    rmse = np.sqrt(target) / float(reference.mean())
    return Record(
        "render.rgl.sampling_vs_cosine",
        f"RGL glossy plastic (GGX alpha 0.15) by its own warps, preview sphere {width}x{height}, path: "
        f"RMSE {rmse:.3g} x mean at {OWN_SPP} spp (median of {RUNS} seeds)",
        f"the same file by cosine sampling: {spp:.0f} spp to that RMSE "
        f"(measured at {', '.join(str(n) for n, _ in levels)} spp)",
        spp / OWN_SPP,
        spp,
        "spp",
    )
