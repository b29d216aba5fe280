"""Running a render: `patina render` and `patina preview`.

The render runs on worker threads in C++; this side shows progress (samples/s, rays/s,
time left) and turns Ctrl-C into a cancel: the passes that finished make a valid, noisier
image, flagged as partial in its metadata.
"""

from __future__ import annotations

import math
import os
import sys
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.native import _core
from patina.render.prepare import PreparedScene
from patina.scene.types import Scene
from patina.widths import core_width

UNBOUNDED_DEPTH = 64  # a Mitsuba-style max_depth of -1 ("unbounded"); Russian roulette ends paths long before


@dataclass
class RenderResult:
    """A finished (or interrupted) render: linear images and what it took."""

    rgb: np.ndarray  # (H, W, 3) radiance, W/(m^2 sr)
    albedo: np.ndarray  # (H, W, 3)
    normal: np.ndarray  # (H, W, 3) world-space shading normal at the first hit
    depth: np.ndarray  # (H, W) distance to the first hit, inf where nothing was hit
    illuminance: np.ndarray  # (H, W) direct illuminance at the first hit, lux
    samples: np.ndarray  # (H, W) samples each pixel got
    spp: int
    seconds: float
    rays: int
    complete: bool
    simd_width: int
    threads: int


def core_depth(scene: Scene) -> int:
    """The C++ integrator's bounce limit from the scene's (Mitsuba-style) max_depth and integrator."""
    if scene.render.integrator == "direct":
        return 1
    depth = scene.render.max_depth
    return UNBOUNDED_DEPTH if depth < 0 else max(1, depth - 1)


class _Progress:
    """One line on stderr: a bar, samples/s, rays/s, time left. Quiet when not a terminal."""

    def __init__(self, enabled: bool) -> None:
        self.enabled = enabled and sys.stderr.isatty()
        self.last = 0.0

    def update(self, p: dict[str, Any], final: bool = False) -> None:
        if not self.enabled or (not final and time.monotonic() - self.last < 0.25):
            return
        self.last = time.monotonic()
        done, total, secs = p["items_done"], max(1, p["items_total"]), max(p["seconds"], 1e-9)
        frac = done / total
        left = secs * (1 - frac) / frac if frac > 0 else float("nan")
        bar = "#" * int(30 * frac)
        eta = f"{left:5.1f} s left" if math.isfinite(left) else "  ... s left"
        sys.stderr.write(f"\r  [{bar:<30}] {100 * frac:5.1f}%  {p['rays'] / secs / 1e6:6.2f} Mrays/s  {eta}")
        if final:
            sys.stderr.write("\n")
        sys.stderr.flush()


def render(
    scene: Scene,
    threads: int = 0,
    simd: int | None = None,
    progress: bool = False,
    prepared: PreparedScene | None = None,
) -> RenderResult:
    """Renders `scene` (its render settings as given: apply CLI overrides with
    `scene_file.with_overrides` first). simd: SIMD width 1, 4 or 8 (None: PATINA_SIMD or the
    widest; named as the CLI's --simd, `width` being an image's width there)."""
    prep = prepared or PreparedScene(scene)
    if (prep.scene.camera.width, prep.scene.camera.height) != (scene.camera.width, scene.camera.height):
        raise ValueError(
            f"the prepared scene renders {prep.scene.camera.width}x{prep.scene.camera.height}, this scene "
            f"{scene.camera.width}x{scene.camera.height}: prepare the scene as it is rendered"
        )
    core_simd = core_width(simd)
    job = _core.RenderJob(
        prep.core,
        spp=scene.render.spp,
        max_depth=core_depth(scene),
        seed=scene.render.seed,
        threads=threads,
        width=core_simd,
    )
    bar = _Progress(progress)
    interrupted = False
    job.start()
    try:
        while not (p := job.progress())["finished"]:
            bar.update(p)
            time.sleep(0.05)
    except KeyboardInterrupt:
        interrupted = True
        job.cancel()
        if progress:
            sys.stderr.write("\n  interrupted: finishing the tiles in flight, keeping every finished pass\n")
    job.wait()
    p = job.progress()
    bar.update(p, final=True)
    images = job.resolve()
    resolved_threads = threads if threads > 0 else (os.cpu_count() or 1)
    complete = bool(p["finished"]) and not interrupted
    return RenderResult(
        rgb=images["rgb"],
        albedo=images["albedo"],
        normal=images["normal"],
        depth=images["depth"],
        illuminance=images["illuminance"],
        samples=images["samples"],
        spp=scene.render.spp,
        seconds=float(p["seconds"]),
        rays=int(p["rays"]),
        complete=complete,
        simd_width=core_simd if core_simd else _core.default_width(),
        threads=resolved_threads,
    )
