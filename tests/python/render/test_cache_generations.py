"""The radiance cache's own noise averages out with samples (issue 31; docs/radiance-cache.md,
"Generations"): `cache` builds its regions' cache points again every generation of passes
(render/cache/cache_generations.h), so at 64 samples a pixel (four generations) the error
that pixels share -- the luminance error against the converged reference averaged over
8 x 8-pixel squares, where the pixels' own noise averages away -- is clearly below the same
render's in one pass, whose one generation of cache points serves all 64 samples (as every
render's did before). cache-studio at half its size (96 x 72: a pixel is 2 x 2 of the bundled
192 x 144 reference), seed 0: 0.0049 in one generation, 0.0037 in four. A few seconds on two
threads. And with adaptive antialiasing (a generation: 16 of its patterns) the regions of
each generation are built once whichever thread asks: the same image at any width and thread
count."""

from __future__ import annotations

import numpy as np
import pytest

from patina.bench.block_steps import luminance
from patina.bench.convergence import integrator_missing
from patina.bundled import materials_path
from patina.native import _core
from patina.render.images import read_image
from patina.render.run import PreparedScene, job_settings, new_job, render
from patina.scene.reading import load_scene, with_overrides

SPP = 64  # four generations of 16 samples
SHRINK = 2  # the render's pixel: SHRINK x SHRINK of the reference's
SQUARE = 8  # pixels a side of the squares the error is averaged over (a quarter region)
# the shared error in four generations at most this fraction of one generation's: pure noise
# would give 1/2; what the cache's placement and reprojection bias share does not average
BOUND = 0.85


def shared_error(rgb: np.ndarray, reference: np.ndarray) -> float:
    """RMS of the luminance error of `rgb` against `reference`, averaged over SQUARE x SQUARE squares."""
    error = luminance(np.asarray(rgb, np.float64)) - luminance(reference)
    h, w = (n - n % SQUARE for n in error.shape)
    squares = error[:h, :w].reshape(h // SQUARE, SQUARE, w // SQUARE, SQUARE).mean(axis=(1, 3))
    return float(np.sqrt(np.mean(squares**2)))


def test_the_cache_error_pixels_share_falls_with_generations():
    reference = read_image(materials_path("references", "cache-studio-path-4096spp.exr"))[..., :3]
    h, w = reference.shape[0] // SHRINK, reference.shape[1] // SHRINK
    reference = reference.astype(np.float64).reshape(h, SHRINK, w, SHRINK, 3).mean(axis=(1, 3))
    full = load_scene(materials_path("scenes", "cache-studio.json"))
    scene = with_overrides(full, integrator="cache", spp=SPP, seed=0, width=w, height=h)
    why = integrator_missing(scene, "cache")
    if why is not None:
        pytest.skip(why)
    prepared = PreparedScene(scene)

    def rendered(max_pass_spp: int) -> np.ndarray:
        options = job_settings(scene)
        options.max_pass_spp = max_pass_spp
        job = new_job(prepared, options, 2)
        job.start()
        job.wait()
        return job.resolve().rgb

    one_generation = shared_error(rendered(SPP), reference)
    generations = shared_error(rendered(16), reference)
    assert generations < BOUND * one_generation, (generations, one_generation)


def test_adaptive_antialiasing_over_two_generations_gives_the_same_image_for_any_width_and_thread_count():
    room = load_scene(materials_path("scenes", "cache-room.json"))
    scene = with_overrides(room, spp=17, width=48, height=32, integrator="cache")  # pattern 17: generation 1
    prepared = PreparedScene(scene)
    base = render(scene, aa="adaptive", simd=1, threads=1, prepared=prepared)
    first = render(with_overrides(scene, spp=16), aa="adaptive", simd=1, threads=1, prepared=prepared)
    assert base.cache_points > first.cache_points  # the regions built again for the second generation
    for simd, threads in ((4, 3), (8, 2), (16, 1)):
        if not _core.width_supported(simd):
            continue
        r = render(scene, aa="adaptive", simd=simd, threads=threads, prepared=prepared)
        assert np.array_equal(r.rgb, base.rgb), (simd, threads)
        assert r.cache_points == base.cache_points
