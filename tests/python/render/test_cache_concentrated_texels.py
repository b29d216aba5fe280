"""More paths where a cache point's light sits in a few texels (render/cache/concentrated_texels.h;
docs/radiance-cache.md, "A cache point's light in a few texels"): which texels take them is
decided in texel order by scalar code, so `cache` on cache-room, whose cache points have such
texels at this size (the refinement adds 591 of its 280 850 rays: tools/render_digest.py's
counts), gives width 1's image at every SIMD width and the same image on one thread and two.
The refinement's effect on a texture is tested in tests/cpp/render/cache/test_concentrated_texels.cpp."""

from __future__ import annotations

import numpy as np
import pytest

from patina.bench.convergence import integrator_missing
from patina.bundled import materials_path
from patina.native import _core
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides


def test_every_width_and_thread_count_gives_the_same_image():
    scene = with_overrides(
        load_scene(materials_path("scenes", "cache-room.json")), integrator="cache", spp=2, width=40, height=30, seed=0
    )
    why = integrator_missing(scene, "cache")
    if why is not None:
        pytest.skip(why)
    prepared = PreparedScene(scene)
    one = render(scene, threads=1, simd=1, prepared=prepared)
    for width in (w for w in (1, 4, 8, 16) if _core.width_supported(w)):
        for threads in (1, 2):
            got = render(scene, threads=threads, simd=width, prepared=prepared)
            assert np.array_equal(got.rgb, one.rgb), f"width {width}, {threads} threads"
            assert got.rays == one.rays, f"width {width}, {threads} threads"
