"""One render's tiles x sample passes as Dask tasks: `patina render SCENE --scheduler ADDRESS`
(or `--workers N`, a LocalCluster), the same image bit for bit as the render on this machine.

The C++ job (render/render_job.h) adds each tile's passes in order, with counter-based random
numbers, so a pixel's sum depends on the seed only. Here the tiles are split into groups (a
few per worker thread, each of tiles from all over the image so that they cost alike) and the passes into runs (the
first pass alone, the others in a few runs: pass_runs); each (group, run) is a task that
takes the group's sums after the earlier passes, renders its passes into them and returns
them. A group's task depends on its task of the passes before, so every addition happens in
the order the local job makes it, and the last sums, copied into a film here, resolve to the
very same floats. (Adding per-pass sums together afterwards would not: floating-point
addition is not associative.) Dask runs a group's next run where its sums already are.

The scene reaches each worker once: the parsed scene and the bytes of every file it reads
(meshes, tables, maps, luminaires) are scattered to every worker as one `SceneBundle`, and
each worker process prepares it once (kd-tree, materials) and keeps the prepared scene and a
job, keyed by the bundle's checksum, for all its tasks.

Ctrl-C, as locally (patina.render.run): the first cancels every task of a later pass and waits
for the first pass, keeping each group's last finished run of passes (a valid, noisier image, flagged
partial); a second cancels everything and raises RenderAborted.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import os
import pickle
import shutil
import tempfile
import threading
import time
import uuid
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.native import _core
from patina.progress import Progress
from patina.render.prepare import PreparedScene
from patina.render.run import POLL_S, RenderAborted, RenderResult, check_prepared, job_settings, render_result
from patina.scene.types import Scene

GROUPS_PER_THREAD = 2  # tile groups a worker thread (each spread over the image: tile_groups)
PASS_RUNS = 8  # a group's passes in at most this many tasks: the first pass alone, the rest in runs
# ... and no more tasks than make this many camera samples each: a task costs Dask some
# milliseconds of CPU on the scheduler and the worker (measured on this project's machine), so
# it should trace for a tenth of a second or more
MIN_TASK_SAMPLES = 1 << 18
RETRIES = 2  # a task that raised is run up to this many times more (a dead worker's are rerun anyway)
CACHED_SCENES = 2  # prepared scenes a worker process keeps (the newest)


# ---------------------------------------------------------------- the scene, shipped once


@dataclass(frozen=True)
class SceneBundle:
    """A scene as a worker needs it without seeing this machine's files: the parsed scene, the
    bytes of every file it reads, the job settings. `scene_checksum` names what the prepared
    scene depends on (all but the render settings: another spp or seed reuses it), `checksum`
    all of it."""

    scene: Scene
    files: dict[str, bytes]  # path in `scene` -> content
    settings: dict[str, Any]  # job_settings
    scene_checksum: str
    checksum: str


def _map_files(obj: Any, change: Any) -> Any:
    """`obj` (a scene or a part of it) with every `file` field's path replaced by change(path)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        new = {}
        for f in dataclasses.fields(obj):
            if not f.init:
                continue
            value = getattr(obj, f.name)
            mapped = change(value) if f.name == "file" and isinstance(value, str) else _map_files(value, change)
            if mapped is not value:
                new[f.name] = mapped
        return dataclasses.replace(obj, **new) if new else obj
    if isinstance(obj, dict):
        mapped_items = {k: _map_files(v, change) for k, v in obj.items()}
        return mapped_items if any(mapped_items[k] is not v for k, v in obj.items()) else obj
    if isinstance(obj, tuple):
        mapped_tuple = tuple(_map_files(v, change) for v in obj)
        return mapped_tuple if any(a is not b for a, b in zip(mapped_tuple, obj)) else obj
    return obj


def scene_files(scene: Scene) -> list[str]:
    """The files `scene` reads when it is prepared, in the order they appear."""
    found: list[str] = []

    def note(path: str) -> str:
        if path not in found:
            found.append(path)
        return path

    _map_files(scene, note)
    return found


def bundle_scene(scene: Scene, settings: dict[str, Any]) -> SceneBundle:
    """The scene, its files' bytes and the job settings, with their checksum."""
    files = {}
    for path in scene_files(scene):
        with open(path, "rb") as f:
            files[path] = f.read()
    digest = hashlib.sha256(pickle.dumps(dataclasses.replace(scene, render=None), protocol=4))
    for path, data in files.items():
        digest.update(path.encode())
        digest.update(hashlib.sha256(data).digest())
    scene_checksum = digest.hexdigest()
    digest.update(pickle.dumps(sorted(settings.items()), protocol=4))
    return SceneBundle(scene, files, settings, scene_checksum, digest.hexdigest())


# ---------------------------------------------------------------- on a worker


@dataclass
class _WorkerJob:
    job: Any  # a _core.RenderJob never started: its film holds the tiles being rendered
    tile_locks: list[threading.Lock]  # a tile's sums are written, rendered and read whole by one task


_scenes: OrderedDict[str, PreparedScene] = OrderedDict()  # by scene_checksum, the newest last
_jobs: OrderedDict[str, _WorkerJob] = OrderedDict()  # by checksum
_cache_lock = threading.Lock()
prepared_here: list[str] = []  # the scene_checksums of the scenes this process prepared (tests: once a worker)


def _prepare(bundle: SceneBundle) -> PreparedScene:
    """The bundle's files written to a temporary folder (the scene pointed at them), prepared,
    and the folder removed: a prepared scene holds everything it read."""
    folder = tempfile.mkdtemp(prefix="patina-scene-")
    try:
        local = {}
        for i, (path, data) in enumerate(bundle.files.items()):
            os.makedirs(os.path.join(folder, str(i)))
            local[path] = os.path.join(folder, str(i), os.path.basename(path))  # the name: formats go by extension
            with open(local[path], "wb") as f:
                f.write(data)
        prepared = PreparedScene(_map_files(bundle.scene, lambda p: local.get(p, p)))
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    prepared_here.append(bundle.scene_checksum)
    return prepared


def _cached(cache: OrderedDict, key: str, make: Any) -> Any:
    if key in cache:
        cache.move_to_end(key)
    else:
        cache[key] = make()
        while len(cache) > CACHED_SCENES:
            cache.popitem(last=False)
    return cache[key]


def _worker_job(bundle: SceneBundle) -> _WorkerJob:
    """This process's job for the bundle: its scene prepared once, kept for the next renders."""
    with _cache_lock:
        prepared = _cached(_scenes, bundle.scene_checksum, lambda: _prepare(bundle))

        def make() -> _WorkerJob:
            job = _core.RenderJob(prepared.core, threads=1, **bundle.settings)
            return _WorkerJob(job, [threading.Lock() for _ in range(job.tile_count)])

        return _cached(_jobs, bundle.checksum, make)


def _zeros(job: Any, tile: int) -> dict[str, np.ndarray]:
    """A tile's sums before its first pass (the worker's job may hold another render's)."""
    return {name: np.zeros_like(values) for name, values in job.read_tile(tile).items()}


def render_passes(
    bundle: SceneBundle, tiles: tuple[int, ...], passes: tuple[int, int], before: dict | None
) -> dict[str, Any]:
    """The Dask task: passes [first, end) of `tiles`, continuing from `before` (the same tiles
    after the earlier passes, None for the first); their sums after them, with the rays and
    camera samples of the passes so far."""
    here = _worker_job(bundle)
    job = here.job
    out: dict[str, Any] = {
        "tiles": {},
        "rays": before["rays"] if before is not None else 0,
        "samples": before["samples"] if before is not None else 0,
        "simd_width": bundle.settings["width"],
    }
    with contextlib.ExitStack() as locked:
        for tile in tiles:  # in increasing order, as every task takes them: no deadlock
            locked.enter_context(here.tile_locks[tile])
        for tile in tiles:
            job.write_tile(tile, **(before["tiles"][tile] if before is not None else _zeros(job, tile)))
        work = job.render_tiles(list(tiles), *passes)
        out["tiles"] = {tile: job.read_tile(tile) for tile in tiles}
    out["rays"] += work["rays"]
    out["samples"] += work["samples"]
    out["simd_width"] = out["simd_width"] or _core.default_width()
    return out


# ---------------------------------------------------------------- the client


def tile_groups(tiles: int, groups: int) -> list[tuple[int, ...]]:
    """Tiles 0 .. tiles-1 dealt into `groups` (tile t to group t mod groups): each group
    takes tiles from all over the image, sky and object alike, so the groups cost about the
    same and a few of them keep the workers evenly busy."""
    groups = max(1, min(groups, tiles))
    return [tuple(range(g, tiles, groups)) for g in range(groups)]


def task_shape(tiles: int, passes: int, threads: int, samples: int) -> tuple[int, int]:
    """(tile groups, pass runs) for a render of `samples` camera samples on `threads` worker
    threads: GROUPS_PER_THREAD x PASS_RUNS tasks when the render is big enough, fewer runs and
    then fewer groups (not under one a thread, nor under two runs: the first pass alone) when
    that would make tasks of under MIN_TASK_SAMPLES."""
    most = max(1, samples // MIN_TASK_SAMPLES)
    groups = min(tiles, GROUPS_PER_THREAD * max(threads, 1))
    runs = max(min(PASS_RUNS, passes, most // groups), min(2, passes))
    while groups * runs > most and groups > min(tiles, max(threads, 1)):
        groups -= 1
    return groups, runs


def pass_runs(passes: int, runs: int = PASS_RUNS) -> list[tuple[int, int]]:
    """Passes 0 .. passes-1 as [first, end) runs, one task each: the first pass alone (what a
    cancel waits for, as locally), the others in at most runs - 1 runs of consecutive passes,
    so a render of many passes (the adaptive sampler's: one a sample) is not thousands of tasks."""
    rest = passes - 1
    n = min(rest, max(runs - 1, 1))
    return [(0, 1)] + [(1 + rest * k // n, 1 + rest * (k + 1) // n) for k in range(n)]


def _wait(news: threading.Event, seconds: float) -> None:
    """Until a task is done (`news` is set by the futures' callbacks), or `seconds`; a test
    replaces it to interrupt the render. A lock's wait: Ctrl-C interrupts it."""
    news.wait(seconds)
    news.clear()


def render_on_dask(
    scene: Scene,
    client: Any,
    simd: int | None = None,
    progress: bool = False,
    prepared: PreparedScene | None = None,
    aa: str | None = None,
    aa_threshold: float | None = None,
    groups: int | None = None,
) -> RenderResult:
    """Renders `scene` as `patina.render.run.render` does, on the workers of a Dask `client`:
    the same image bit for bit. groups: tile groups (default: task_shape's). The prepared
    scene here only merges the tiles (and checks the scene before anything is sent); the
    workers prepare their own. Ctrl-C: see the module docstring."""
    from distributed import Future

    settings = job_settings(scene, simd, aa, aa_threshold)
    prep = check_prepared(scene, prepared)
    merged = _core.RenderJob(prep.core, threads=1, **settings)
    threads = sum(client.nthreads().values())
    pixels = scene.camera.width * scene.camera.height
    shape = task_shape(merged.tile_count, merged.pass_count, threads, pixels * scene.render.spp)
    plan = tile_groups(merged.tile_count, groups or shape[0])
    runs = pass_runs(merged.pass_count, shape[1])
    start = time.perf_counter()
    run_id = uuid.uuid4().hex[:12]
    # pending[(g, r)]: group g's run r, not yet seen done; last[g]: its last finished run
    pending: dict[tuple[int, int], Future] = {}
    last: dict[int, tuple[int, Future]] = {}
    bundle = None

    def harvest() -> None:
        for key in [k for k, f in pending.items() if f.done()]:
            future = pending.pop(key)
            if future.status == "error":
                raise future.exception()
            if future.status == "finished" and key[1] > last.get(key[0], (-1, None))[0]:
                last[key[0]] = (key[1], future)  # the earlier run's sums are released

    news = threading.Event()  # set when a task is done: the loop below looks then, not by polling
    interrupts = 0
    try:
        bundle = client.scatter(bundle_scene(scene, settings), broadcast=True, hash=False)
        for r, passes in enumerate(runs):
            for g, tiles in enumerate(plan):
                pending[(g, r)] = client.submit(
                    render_passes, bundle, tiles, passes, pending[(g, r - 1)] if r > 0 else None,
                    key=f"patina-render-{run_id}-passes{passes[0]}-{passes[1]}-group{g}", pure=False,
                    retries=RETRIES, priority=len(runs) - r,  # pass by pass, as the local job takes them
                )  # fmt: skip
                pending[(g, r)].add_done_callback(lambda _: news.set())
        total = len(pending)
        with Progress(total, "rendering", unit="task", enabled=progress) as bar:
            while pending:
                try:
                    _wait(news, POLL_S)
                    harvest()
                    if pending:
                        passes = runs[min(k[1] for k in pending)]
                        bar.update(total - len(pending), postfix=f"passes {passes[0] + 1}-{passes[1]} of {runs[-1][1]}")
                except KeyboardInterrupt:
                    interrupts += 1
                    if interrupts >= 2:
                        raise RenderAborted("the render was aborted by a second interrupt; nothing was kept") from None
                    bar.write(
                        "  interrupted: finishing the first pass, keeping every finished pass "
                        "(Ctrl-C again aborts, keeping nothing)"
                    )
                    harvest()
                    later = [k for k in pending if k[1] > 0]
                    client.cancel([pending.pop(k) for k in later])
            bar.update(total)
            results = client.gather([last[g][1] for g in range(len(plan))])
    except BaseException:
        client.cancel(list(pending.values()))
        raise
    finally:
        if bundle is not None:
            bundle.release()
    for tiles, result in zip(plan, results):
        for tile in tiles:
            merged.write_tile(tile, **result["tiles"][tile])
    complete = all(last[g][0] == len(runs) - 1 for g in range(len(plan)))
    return render_result(
        scene,
        merged.resolve(),
        settings,
        seconds=time.perf_counter() - start,
        rays=sum(r["rays"] for r in results),  # of the passes kept (a cancelled task's rays are lost with it)
        camera_rays=sum(r["samples"] for r in results),
        complete=complete,
        threads=threads,
        simd_width=results[0]["simd_width"],
        interrupted=interrupts > 0,
    )
