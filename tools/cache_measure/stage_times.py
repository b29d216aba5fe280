"""`cache`'s CPU time per stage (`RenderJob.stage_times()`, the thread's CPU clock) on the
bundled cache scenes at the bench's size (bench/cache.py FULL: 192 pixels wide, 16 spp), one
thread, the median of REPEAT renders per width (docs/radiance-cache.md, "Figures against the
issue's targets"). Run from the checkout: python tools/cache_measure/stage_times.py [16,8]
(SCENES=cache-room,... and REPEAT=3)."""

import os
import statistics
import sys

from patina.bench.cache import FULL
from patina.bench.convergence import sized
from patina.bundled import materials_path
from patina.render.run import PreparedScene, job_settings, new_job
from patina.scene.reading import load_scene, with_overrides

widths = [int(w) for w in (sys.argv[1] if len(sys.argv) > 1 else "16").split(",")]
repeat = int(os.environ.get("REPEAT", "3"))
scenes = os.environ.get("SCENES", "cache-room,cache-studio,cache-ies-interior").split(",")


def stage_ms(prep: PreparedScene, scene, width: int) -> dict[str, float]:
    options = job_settings(scene, width, None, None, None)
    options.stage_clock = "cpu"
    job = new_job(prep, options, threads=1)
    job.start()
    job.wait()
    times = job.stage_times()
    out = {k: 1e3 * v for k, v in times.stages.items() if k.startswith("cache_")}
    out["total"] = 1e3 * times.item_seconds
    return out


for name in scenes:
    scene = sized(load_scene(materials_path("scenes", f"{name}.json")), FULL.width)
    scene = with_overrides(scene, integrator="cache", spp=FULL.candidate_spp)
    prep = PreparedScene(scene)
    for w in widths:
        runs = [stage_ms(prep, scene, w) for _ in range(repeat)]
        med = {k: statistics.median(r[k] for r in runs) for k in runs[0]}
        load = open("/proc/loadavg").read().split()[0]
        print(name, f"width {w}:", " ".join(f"{k} {v:.0f}" for k, v in med.items()), "ms, load", load, flush=True)
