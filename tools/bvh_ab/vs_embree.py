"""The BVH against Embree (embreex) on the trace bench's ray sets in CPU time, one thread:
`accel.core.intersect(..., bvh=True)` / `occluded` (allocating their results, as the bench's
`bvh_vs_embree` records) against `EmbreeScene.run`, interleaved, medians. CPU time, because on a
loaded machine the bench's wall clock of a 5 ms run is mostly the waits for a core.
    .venv/bin/python tools/bvh_ab/vs_embree.py [REPEAT]      (from the checkout)
"""

import functools
import sys
import time
from collections.abc import Callable

import numpy as np

from patina.bench import trace as bench
from patina.bench.ray_replay import recorded_preview
from patina.geometry import benchmark_geometry as scenes
from patina.geometry.accel import Accel


def cpu_medians(f: Callable[[], object], g: Callable[[], object], repeat: int) -> tuple[float, float]:
    times: tuple[list[float], list[float]] = ([], [])
    for k in range(repeat):
        for which in (0, 1) if k % 2 == 0 else (1, 0):
            start = time.process_time()
            (f, g)[which]()
            times[which].append(time.process_time() - start)
    return float(np.median(times[0])), float(np.median(times[1]))


def ray_sets() -> list[tuple[str, Accel, object, scenes.Rays, np.ndarray | None]]:
    sets = []
    for sc in bench._scenes(False)[:2]:  # icosphere, box field
        accel, embree = Accel(sc.mesh), bench._embree_scene(sc.mesh)
        primary = scenes.pinhole_rays(sc.side, sc.side, sc.eye, sc.target, sc.fov_deg)
        if sc.name == "icosphere":
            sets.append(("primary.icosphere", accel, embree, primary, None))
        sets.append((f"random.{sc.name}", accel, embree, scenes.diffuse_bounce_rays(accel, primary, seed=4), None))
        if sc.name == "boxes":
            shadow, tmax = bench._shadow_rays(accel, primary, np.array([0.6, -0.4, 2.5]))
            sets.append(("shadow.boxes", accel, embree, shadow, tmax))
    rec = recorded_preview(False)
    accel, embree = Accel(rec.mesh), bench._embree_scene(rec.mesh)
    sets.append(("replay.preview.path", accel, embree, scenes.Rays(*rec.closest), None))
    so, sd, tmax = rec.shadow
    sets.append(("replay.preview.shadow", accel, embree, scenes.Rays(so, sd), tmax))
    return sets


def main() -> None:
    repeat = int(sys.argv[1]) if len(sys.argv) > 1 else 11
    for name, accel, embree, (o, d), tmax in ray_sets():
        accel.core.build_bvh()
        if tmax is None:
            mine = functools.partial(accel.core.intersect, o, d, width=8, threads=1, bvh=True)
            theirs = functools.partial(embree.run, o, d, output=1)
        else:
            mine = functools.partial(accel.core.occluded, o, d, tmax=tmax, width=8, threads=1, bvh=True)
            theirs = functools.partial(embree.run, o, d, dists=tmax.copy(), query="OCCLUDED")
        a, b = cpu_medians(mine, theirs, repeat)
        print(f"{name:24s} BVH {a * 1e3:8.2f} ms  Embree {b * 1e3:8.2f} ms  Embree/BVH {b / a:.3f}")


if __name__ == "__main__":
    main()
