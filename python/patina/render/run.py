"""Running a render: `patina render` and `patina preview`.

The render runs on worker threads in C++; this side shows progress (patina.progress: samples
per pixel done, rays/s, time left) and turns Ctrl-C into a cancel:

- the first Ctrl-C stops the render once its first pass is complete (every pixel has at
  least one sample), keeping every finished pass: a valid, noisier image, flagged as
  partial in its metadata (`RenderResult.complete` false);
- a second Ctrl-C aborts at once: `RenderAborted` is raised and there is no image (the
  pixels of an unfinished first pass have no sample, so nothing is worth keeping).
"""

from __future__ import annotations

import copy
import dataclasses
import os
import threading

import numpy as np

from patina.native import _core
from patina.progress import Progress
from patina.render.prepare import PreparedScene
from patina.scene.types import CacheParams, Scene
from patina.widths import core_width

POLL_S = 0.1  # how often the progress display and Ctrl-C are looked at while a render runs


class RenderAborted(KeyboardInterrupt):
    """A render stopped by a second interrupt: there is no image to keep."""


@dataclasses.dataclass
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
    interrupted: bool = False  # Ctrl-C (or SIGTERM in the CLI) came; the image may still be complete
    aa: str = "uniform"  # the pixel sampler (docs/antialiasing.md)
    aa_threshold: float = 0.15
    sampler: str = "sobol"  # the paths' numbers (docs/render.md)
    camera_rays: int = 0  # camera rays traced (the adaptive sampler: its positions, each one integrator sample)
    aa_level: np.ndarray | None = None  # (H, W) adaptive: 1, 2 or 3, the level each pixel reached
    aa_rays: np.ndarray | None = None  # (H, W) adaptive: the pixel's own rays a pass (1 = its share of the corners)
    # the radiance cache (integrators cache, cache-guided; docs/radiance-cache.md): cache points
    # built, first-hit points served, and of their hemispheres' texels how many were
    # reprojected (or known empty) and how many traced
    cache_points: int = 0
    cache_queries: int = 0
    cache_texels_reprojected: int = 0
    cache_texels_traced: int = 0


CACHE_COUNTS = ("cache_points", "cache_queries", "cache_texels_reprojected", "cache_texels_traced")
DIRECT_DEPTH = 2  # the `direct` integrator: the path tracer at max_depth 2 (emitters and direct light)


class _Waiter(threading.Thread):
    """Joins the C++ workers (job.wait releases the GIL) so the main thread stays free to
    show progress and to take a second Ctrl-C while a cancelled job winds down."""

    def __init__(self, job: _core.RenderJob) -> None:
        super().__init__(name="patina-render-wait", daemon=True)
        self.job = job
        self.error: BaseException | None = None
        # set last; waited on with a timeout, not join(): a KeyboardInterrupt inside Thread.join
        # can mark a running thread stopped (CPython 3.11, bpo-45274's fix), and resolving a job
        # whose workers still run reads a half-written film. An event, not a flag polled with
        # sleep, so a short render returns when it ends, not up to a poll period later.
        self.finished = threading.Event()

    def run(self) -> None:
        try:
            self.job.wait()
        except BaseException as e:  # a worker's exception, re-raised in the caller's thread
            self.error = e
        self.finished.set()


def render_threads(threads: int) -> int:
    """The threads a render job runs for `threads` (0: one a core)."""
    return threads or os.cpu_count() or 1


def _run_job(job: _core.RenderJob, pixels: int, spp: int, progress: bool, by_items: bool = False) -> bool:
    """Runs `job` to its end, showing progress; True if it was interrupted (once). by_items:
    spp counted from the work items done (the adaptive sampler's samples a pixel vary)."""
    interrupts = 0
    with Progress(spp, "rendering", unit="spp", enabled=progress) as bar:

        def show() -> None:
            p = job.progress()
            if p.preparing:  # the adaptive sampler's geometric pre-pass, before any pass
                bar.update(0, postfix=f"geometric pre-pass, {p.seconds:.1f} s")
                return
            rate = p.rays / max(p.seconds, 1e-9) / 1e6
            done = spp * p.items_done / max(p.items_total, 1) if by_items else p.samples_done / pixels
            bar.update(round(done, 1), postfix=f"{rate:.2f} Mrays/s")

        job.start()
        waiter = _Waiter(job)
        waiter.start()
        told = 0
        # the loop leaves only when the workers have stopped (a Python exit with C++ workers
        # still running can crash); the handler is two steps, the messages come from the loop
        while not waiter.finished.is_set():
            try:
                if told < min(interrupts, 2):
                    told += 1
                    bar.write(
                        "  interrupted: finishing the first pass and the tiles in flight, keeping every "
                        "finished pass (Ctrl-C again aborts, keeping nothing)"
                        if told == 1
                        else "  interrupted again: aborting, nothing is kept"
                    )
                waiter.finished.wait(POLL_S)
                show()
            except KeyboardInterrupt:
                interrupts += 1
                job.cancel()  # the first: after the first pass; the second: now
        if waiter.error is not None:
            raise waiter.error
        show()
    if interrupts >= 2:
        raise RenderAborted("the render was aborted by a second interrupt; nothing was kept")
    return interrupts > 0


def job_settings(
    scene: Scene,
    simd: int | None = None,
    aa: str | None = None,
    aa_threshold: float | None = None,
    sampler: str | None = None,
) -> _core.RenderOptions:
    """The `_core.RenderOptions` of `scene` (all but the thread count): what makes its image,
    so a distributed render (patina.batch.render_tiles) gives the same. simd, aa,
    aa_threshold, sampler: as `render`. ValueError naming a setting out of its range."""
    r = scene.render
    options = _core.RenderOptions(
        spp=r.spp,
        max_depth=path_depth(scene),
        seed=r.seed,
        width=core_width(simd),
        aa=r.aa if aa is None else aa,
        aa_threshold=r.aa_threshold if aa_threshold is None else aa_threshold,
        indirect_illuminance=r.indirect_illuminance,
        sampler=r.sampler if sampler is None else sampler,
        integrator="path" if r.integrator == "direct" else r.integrator,
        cache=cache_settings(r.cache),
    )
    options.check()
    return options


def path_depth(scene: Scene) -> int:
    """The max_depth `scene`'s paths are traced to: render.max_depth, or DIRECT_DEPTH for the
    `direct` integrator (the path tracer cut to direct light)."""
    return DIRECT_DEPTH if scene.render.integrator == "direct" else scene.render.max_depth


def cache_settings(params: CacheParams) -> _core.CacheSettings:
    """The scene's render.cache as the renderer takes it, key by key."""
    return _core.CacheSettings(**dataclasses.asdict(params))


def new_job(prepared: PreparedScene, options: _core.RenderOptions, threads: int) -> _core.RenderJob:
    """A job of `options` on `threads` worker threads (0: all); `options` is left as it is."""
    options = copy.copy(options)
    options.threads = threads
    return _core.RenderJob(prepared.core, options)


def check_prepared(scene: Scene, prepared: PreparedScene | None) -> PreparedScene:
    """`prepared` (or `scene` prepared now), refused when it was prepared at another size."""
    prep = prepared or PreparedScene(scene)
    if (prep.scene.camera.width, prep.scene.camera.height) != (scene.camera.width, scene.camera.height):
        raise ValueError(
            f"the prepared scene renders {prep.scene.camera.width}x{prep.scene.camera.height}, this scene "
            f"{scene.camera.width}x{scene.camera.height}: prepare the scene as it is rendered"
        )
    return prep


def render_result(
    scene: Scene, images: _core.ResolvedImages, settings: _core.RenderOptions, *,
    seconds: float, rays: int, camera_rays: int, complete: bool,
    threads: int, simd_width: int, interrupted: bool, cache: dict | None = None,
) -> RenderResult:  # fmt: skip
    """A RenderResult from a job's resolved `images` and its `settings` (job_settings);
    `cache`: the job's radiance-cache counts (CACHE_COUNTS of its progress), if any."""
    # the adaptive sampler's weights sum to 1 a pass up to float rounding
    if float(images.samples.min()) < 1 - 1e-4:
        # cannot happen (a cancel finishes the first pass); never hand out unsampled pixels
        raise RuntimeError("the render stopped with pixels that have no sample")
    return RenderResult(
        rgb=images.rgb,
        albedo=images.albedo,
        normal=images.normal,
        depth=images.depth,
        illuminance=images.illuminance,
        samples=images.samples,
        spp=scene.render.spp,
        seconds=seconds,
        rays=rays,
        complete=complete,
        simd_width=simd_width,
        threads=threads,
        interrupted=interrupted,
        aa=settings.aa,
        aa_threshold=float(str(np.float32(settings.aa_threshold))),  # the float32 taken, as its shortest decimal
        sampler=settings.sampler,
        camera_rays=camera_rays,
        aa_level=images.aa_level,
        aa_rays=images.aa_rays,
        **{k: int((cache or {}).get(k, 0)) for k in CACHE_COUNTS},
    )


def render(
    scene: Scene,
    threads: int = 0,
    simd: int | None = None,
    progress: bool = False,
    prepared: PreparedScene | None = None,
    aa: str | None = None,
    aa_threshold: float | None = None,
    sampler: str | None = None,
) -> RenderResult:
    """Renders `scene` (its render settings as given: apply CLI overrides with
    `scene_file.with_overrides` first). simd: SIMD width 1, 4 or 8 (None: PATINA_SIMD or the
    widest; named as the CLI's --simd, `width` being an image's width there). aa: the pixel
    sampler, "uniform" or "adaptive", and aa_threshold its contrast threshold in [0, 1]
    (None: the scene's render.aa, render.aa_threshold; docs/antialiasing.md). sampler: the
    paths' numbers, "sobol" (Owen-scrambled Sobol) or "independent" (None: the scene's
    render.sampler; docs/render.md).
    Ctrl-C: see the module docstring (a second one raises `RenderAborted`)."""
    settings = job_settings(scene, simd, aa, aa_threshold, sampler)
    prep = check_prepared(scene, prepared)
    job = new_job(prep, settings, threads)
    pixels = scene.camera.width * scene.camera.height
    interrupted = _run_job(job, pixels, scene.render.spp, progress, by_items=settings.aa == "adaptive")
    p = job.progress()
    return render_result(
        scene,
        job.resolve(),
        settings,
        seconds=p.seconds,
        rays=p.rays,
        camera_rays=p.samples_done,
        complete=p.finished,  # an interrupt after the last item still leaves a whole image
        threads=render_threads(threads),
        simd_width=settings.width or _core.default_width(),
        interrupted=interrupted,
        cache={k: getattr(p, k) for k in CACHE_COUNTS},
    )
