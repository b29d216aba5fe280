"""The gold sphere's time to equal error against Mitsuba 3 llvm_ad_rgb with each side's sphere
analytic or tessellated, in one process (docs/performance.md, "The analytic gold sphere").

The steps of `_vs_mitsuba_records` (python/patina/bench/render.py: one reference, measured error
curves at 32, 128 and 512 spp, medians of 3, `_seconds_to_error`), for three pairings: Patina's
triangles against Mitsuba's analytic sphere (main's `render.vs_mitsuba_llvm` before Patina had
the exact sphere), both analytic (the record now), both on Patina's triangles (`.triangles`).
Usage: .venv/bin/python tools/vs_mitsuba_geometry.py
"""

from __future__ import annotations

import os

from patina.bench import render as R
from patina.bench.mitsuba_scenes import triangle_spheres
from patina.render.run import PreparedScene
from patina.scene.reading import load_scene, with_overrides


def main() -> None:
    threads = os.cpu_count() or 1
    levels, ref_spp, repeat = [32, 128, 512], 8192, 3
    scene = with_overrides(load_scene(R._scene_path("conductor-sphere")), width=128, height=96, seed=0)
    tri = triangle_spheres(scene)
    print("load", os.getloadavg())
    reference, reference_mse = R._own_reference(R._mitsuba_renderer(scene, "llvm_ad_rgb", threads), ref_spp)

    def curve(render_at):
        return R._error_curve(render_at, levels, reference, reference_mse, repeat)

    def patina(s):
        p = PreparedScene(s)
        return curve(lambda n: R._render(p, s, 0, threads, n))

    def mitsuba(s, triangles):
        return curve(R._mitsuba_renderer(s, "llvm_ad_rgb", threads, stand_ins=triangles, sampler=R.MITSUBA_SAMPLER))

    pa, pt = patina(scene), patina(tri)
    ma, mt = mitsuba(scene, False), mitsuba(tri, True)
    for name, p, m in [
        ("Patina triangles vs Mitsuba analytic (main's record)", pt, ma),
        ("both analytic (render.vs_mitsuba_llvm)", pa, ma),
        ("both triangles (render.vs_mitsuba_llvm.triangles)", pt, mt),
    ]:
        tp, target = p[-1]
        print(f"{name}: ratio {R._seconds_to_error(m, target) / tp:.3f}, Patina {tp:.3f} s")
    print(f"Patina triangles / analytic at {levels[-1]} spp: {pt[-1][0] / pa[-1][0]:.2f}x")
    print("load", os.getloadavg())


if __name__ == "__main__":
    main()
