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
(meshes with a .gltf's external buffers and images, tables, maps, luminaires) travel as one
`SceneBundle`, scattered to one worker and fetched from there by every other worker its
first task lands on (once: it stays), and each worker process prepares it once (kd-tree,
materials) and keeps the prepared scene and a job, keyed by the bundle's checksum, for all
its tasks.

Ctrl-C, as locally (patina.render.run): the first cancels every task of a later pass and waits
for the first pass, keeping each group's last finished run of passes (a valid, noisier image, flagged
partial); a second cancels everything and raises RenderAborted.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import os
import pickle
import shutil
import tempfile
import threading
import time
import uuid
from collections import OrderedDict
from concurrent.futures import CancelledError
from dataclasses import dataclass
from typing import Any
from urllib.parse import unquote

import numpy as np

from patina.native import _core
from patina.progress import Progress
from patina.render.prepare import PreparedScene
from patina.render.run import (
    CACHE_COUNTS,
    POLL_S,
    RenderAborted,
    RenderResult,
    check_prepared,
    job_settings,
    new_job,
    render_result,
)
from patina.scene.types import Scene

GROUPS_PER_THREAD = 2  # tile groups a worker thread (each spread over the image: tile_groups)
PASS_RUNS = 8  # a group's passes in at most this many tasks: the first pass alone, the rest in runs
# ... and no more tasks than make this many camera samples each: a task costs Dask some
# milliseconds of CPU on the scheduler and the worker (measured on this project's machine), so
# it should trace for a tenth of a second or more
MIN_TASK_SAMPLES = 1 << 18
RETRIES = 2  # a task that raised is run up to this many times more (a dead worker's are rerun anyway)
RESTARTS = 3  # chains broken by dead workers, submitted again from their first pass, in one render
# integrators whose tiles are independent (each pixel a function of the seed only), so that a
# tile rendered in another process is the same: the radiance cache's too, whose cache lives
# for one batch of one (tile, pass) work item (render/cache/radiance_cache_impl.h), nothing
# carried from item to item; an integrator that kept a cache across tiles would not be
TILE_INDEPENDENT = ("direct", "path", "cache", "cache-guided")
CACHED_SCENES = 2  # prepared scenes a worker process keeps (the newest)
COUNTS = ("rays", "samples", *CACHE_COUNTS)  # what a task counts, added up along its chain


# ---------------------------------------------------------------- the scene, shipped once


@dataclass(frozen=True)
class SceneBundle:
    """A scene as a worker needs it without seeing this machine's files: the parsed scene, the
    bytes of every file it reads, the job settings. `scene_checksum` names what the prepared
    scene depends on (all but the render settings: another spp or seed reuses it), `checksum`
    all of it."""

    scene: Scene
    files: dict[str, bytes]  # path in `scene` -> content
    settings: _core.RenderOptions  # job_settings
    scene_checksum: str
    checksum: str
    # path in `scene` -> {the path relative to it of a file it reads in turn: its content}
    # (a .gltf's external .bin buffers and images)
    companions: dict[str, dict[str, bytes]] = dataclasses.field(default_factory=dict)


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


def gltf_companions(path: str, content: bytes) -> list[str]:
    """The files a .gltf may read beside it (its buffers' and images' URIs that are not
    `data:`), as paths relative to its folder. ValueError for one outside that folder: a worker writes
    them beside its copy of the .gltf, and only there."""
    try:
        doc = json.loads(content)
    except ValueError:
        return []  # not JSON: the mesh reader says so, here and on the workers alike
    if not isinstance(doc, dict):
        return []
    found = []
    for key in ("buffers", "images"):
        for entry in doc.get(key) or []:
            uri = entry.get("uri") if isinstance(entry, dict) else None
            if not isinstance(uri, str) or uri.startswith("data:"):
                continue
            # percent-encoded by the glTF spec, taken as written by some readers (trimesh): both
            for relative in dict.fromkeys(os.path.normpath(u) for u in (uri, unquote(uri))):
                if os.path.isabs(relative) or relative.split(os.sep)[0] == "..":
                    raise ValueError(f"{path}: {key} uri {uri!r}: only files in the .gltf's folder go to the workers")
                if relative not in found:
                    found.append(relative)
    return found


def bundle_scene(scene: Scene, settings: _core.RenderOptions) -> SceneBundle:
    """The scene, its files' bytes (and a .gltf's buffers and images) and the job settings,
    with their checksum."""
    files: dict[str, bytes] = {}
    companions: dict[str, dict[str, bytes]] = {}
    for path in scene_files(scene):
        with open(path, "rb") as f:
            files[path] = f.read()
        if path.lower().endswith(".gltf"):
            companions[path] = {}
            for relative in gltf_companions(path, files[path]):
                beside = os.path.join(os.path.dirname(path), relative)
                if os.path.isfile(beside):  # a missing one: the mesh reader's error, as locally
                    with open(beside, "rb") as f:
                        companions[path][relative] = f.read()
    digest = hashlib.sha256(pickle.dumps(dataclasses.replace(scene, render=None), protocol=4))
    for path, data in files.items():
        digest.update(path.encode())
        digest.update(hashlib.sha256(data).digest())
        for relative, extra in companions.get(path, {}).items():
            digest.update(relative.encode())
            digest.update(hashlib.sha256(extra).digest())
    scene_checksum = digest.hexdigest()
    digest.update(repr(settings).encode())  # every option by name
    return SceneBundle(scene, files, settings, scene_checksum, digest.hexdigest(), companions)


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
            for relative, extra in bundle.companions.get(path, {}).items():  # beside it, as it names them
                os.makedirs(os.path.dirname(os.path.join(folder, str(i), relative)), exist_ok=True)
                with open(os.path.join(folder, str(i), relative), "wb") as f:
                    f.write(extra)
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
            job = new_job(prepared, bundle.settings, threads=1)
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
        **{k: before[k] if before is not None else 0 for k in COUNTS},
        "simd_width": bundle.settings.width,
    }
    with contextlib.ExitStack() as locked:
        for tile in tiles:  # in increasing order, as every task takes them: no deadlock
            locked.enter_context(here.tile_locks[tile])
        for tile in tiles:
            job.write_tile(tile, **(before["tiles"][tile] if before is not None else _zeros(job, tile)))
        work = job.render_tiles(list(tiles), *passes)
        out["tiles"] = {tile: job.read_tile(tile) for tile in tiles}
    for k in COUNTS:
        out[k] += getattr(work, k)
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


class _Chains:
    """A distributed render's tasks: for each tile group a chain of runs of passes, each task
    taking the one before it. A group's last run is fetched here as soon as it is done, so a
    worker that dies later loses nothing; a chain a dead worker broke (Dask cannot recompute
    it: the earlier runs' sums were released) is submitted again from its first pass, which
    gives the same sums (RESTARTS at most, then RuntimeError)."""

    def __init__(
        self, client: Any, bundle: SceneBundle, plan: list[tuple[int, ...]], runs: list[tuple[int, int]]
    ) -> None:
        self.client, self.scene_bundle, self.plan, self.runs = client, bundle, plan, runs
        # not broadcast: a worker fetches it with its first task (a worker that joins later too),
        # and a broadcast's replication waited forever on a worker just restarted after a crash
        self.bundle = client.scatter(bundle, hash=False)
        self.run_id = uuid.uuid4().hex[:12]  # keys unique to this render, on a scheduler others share
        self.news = threading.Event()  # set when a task is done: the loop looks then, not by polling
        self.pending: dict[tuple[int, int], Any] = {}  # (group, run) -> its future, not yet seen done
        self.last: dict[int, tuple[int, Any]] = {}  # group -> its last finished run and future
        self.kept: dict[int, tuple[int, dict]] = {}  # group -> the run whose sums came back, and them
        self.end = len(runs)  # the runs each group renders: all, or the first alone after an interrupt
        self.total = self.done = self.restarts = 0
        # the workers' threads, one entry each, dealt the groups in turn
        self.slots = [w for w, n in sorted(client.nthreads().items()) for _ in range(n)]
        for g in range(len(plan)):
            self._submit(g)

    def _submit(self, g: int) -> None:
        before = None
        for r in range(self.end):
            first, end = self.runs[r]
            # a chain's first task where its group is dealt (a hint: another worker may take it).
            # Left to itself Dask put every first task where the scene was scattered, the worker
            # that held their one input, and the others idled until it stole some (0.3 to 0.8 s a
            # render); the later runs go where their sums are
            where = {"workers": [self.slots[g % len(self.slots)]], "allow_other_workers": True} if r == 0 else {}
            before = self.pending[(g, r)] = self.client.submit(
                render_passes, self.bundle, self.plan[g], (first, end), before,
                key=f"patina-render-{self.run_id}-group{g}-passes{first}-{end}-try{self.restarts}", pure=False,
                retries=RETRIES, priority=len(self.runs) - r, **where,  # pass by pass, as the local job takes them
            )  # fmt: skip
            before.add_done_callback(lambda _: self.news.set())
            self.total += 1

    def _restart(self, g: int) -> None:
        self.restarts += 1
        if self.restarts > RESTARTS:
            raise RuntimeError(f"the render lost its workers' results {RESTARTS} times; giving up")
        self.client.cancel([self.pending.pop(k) for k in [k for k in self.pending if k[0] == g]])
        self.last.pop(g, None)
        if self.bundle.status != "finished":  # the scene was lost with the worker that held it
            self.bundle = self.client.scatter(self.scene_bundle, hash=False)
        self._submit(g)

    def _fetch(self, g: int) -> None:
        run, future = self.last.pop(g)
        try:
            self.kept[g] = (run, future.result())
        except CancelledError:  # lost with its worker between finishing and this
            self._restart(g)

    def harvest(self) -> None:
        for key in [k for k, f in self.pending.items() if f.done()]:
            future = self.pending.pop(key, None)
            if future is None:  # its chain was restarted by an earlier key of this look
                continue
            g, r = key
            if future.status == "error":  # the task raised (after its retries), or killed its workers
                raise future.exception()
            if future.status != "finished":  # cancelled, not by us: its chain broke with a dead worker
                self._restart(g)
                continue
            self.done += 1
            if r > self.last.get(g, (-1, None))[0]:
                self.last[g] = (r, future)  # the earlier run's future goes: its sums are released
            if r == self.end - 1:
                self._fetch(g)

    def interrupt(self) -> None:
        """Ctrl-C: the later passes' tasks cancelled, the finished runs kept, the first pass awaited."""
        self.harvest()
        self.end = 1
        later = [k for k in self.pending if k[1] > 0]
        self.client.cancel([self.pending.pop(k) for k in later])
        self.total -= len(later)
        for g in list(self.last):
            if g not in self.kept:
                self._fetch(g)

    def finished(self) -> bool:
        return len(self.kept) == len(self.plan)

    def passes_in_flight(self) -> str:
        if not self.pending:
            return ""
        first, end = self.runs[min(r for _, r in self.pending)]
        return f"passes {first + 1}-{end} of {self.runs[-1][1]}"


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
    if scene.render.integrator not in TILE_INDEPENDENT:
        raise ValueError(
            f"integrator {scene.render.integrator!r}: its tiles share what they learn, so a distributed render "
            f"could not be bit-identical; render it on this machine (distributed: {', '.join(TILE_INDEPENDENT)})"
        )
    settings = job_settings(scene, simd, aa, aa_threshold)
    prep = check_prepared(scene, prepared)
    merged = new_job(prep, settings, threads=1)
    threads = sum(client.nthreads().values())
    pixels = scene.camera.width * scene.camera.height
    shape = task_shape(merged.tile_count, merged.pass_count, threads, pixels * scene.render.spp)
    plan = tile_groups(merged.tile_count, groups or shape[0])
    runs = pass_runs(merged.pass_count, shape[1])
    start = time.perf_counter()
    chains = None
    interrupts = 0
    try:
        chains = _Chains(client, bundle_scene(scene, settings), plan, runs)
        with Progress(chains.total, "rendering", unit="task", enabled=progress) as bar:
            while not chains.finished():
                try:
                    _wait(chains.news, POLL_S)
                    chains.harvest()
                    bar.total = chains.total
                    bar.update(chains.done, postfix=chains.passes_in_flight())
                except KeyboardInterrupt:
                    interrupts += 1
                    if interrupts >= 2:
                        raise RenderAborted("the render was aborted by a second interrupt; nothing was kept") from None
                    bar.write(
                        "  interrupted: finishing the first pass, keeping every finished pass "
                        "(Ctrl-C again aborts, keeping nothing)"
                    )
                    chains.interrupt()
            bar.update(chains.done)
    except BaseException:
        if chains is not None:
            client.cancel(list(chains.pending.values()))
        raise
    finally:
        if chains is not None:
            chains.bundle.release()
    results = [chains.kept[g][1] for g in range(len(plan))]
    for tiles, result in zip(plan, results):
        for tile in tiles:
            merged.write_tile(tile, **result["tiles"][tile])
    complete = all(chains.kept[g][0] == len(runs) - 1 for g in range(len(plan)))
    return render_result(
        scene,
        merged.resolve(),
        settings,
        seconds=time.perf_counter() - start,
        rays=sum(r["rays"] for r in results),  # of the passes kept (a cancelled task's rays are lost with it)
        camera_rays=sum(r["samples"] for r in results),
        complete=complete,
        cache={k: sum(r[k] for r in results) for k in CACHE_COUNTS},
        threads=threads,
        simd_width=results[0]["simd_width"],
        interrupted=interrupts > 0,
    )
