"""`patina bench --only batch`: how well the Dask runs use their workers (docs/bench.md).

- `batch.library.workers2`: `patina batch` of a generated library (plastic tables sampled
  from an analytic BRDF: validated, fitted, previewed) on a LocalCluster of 2 worker
  processes against the same on 1; value = efficiency per worker (speedup / 2).
- `batch.machine.processes2`: the same CPU-bound loop in 2 processes against one after the
  other: what the machine gives 2 workers at all (a machine shared between sessions may give
  one session a core, however many processes it runs), to read the first record by.
- `batch.render.tiles`: the preview ball rendered as tiles on 2 worker processes
  (patina.batch.render_tiles) against the local render on 2 threads; value = the time
  overhead (distributed time / local time - 1).

The clusters are the commands' own (patina.batch.scheduling.connect), started once, before
any timing, and live through the group; each timed run is a whole batch into a fresh folder
(a rerun would skip the work) or a whole render (the workers prepared the scene on the
warm-up run: what is timed is the render; the warm-up's time is in the record's text). Runs
interleave and times are medians, as in every group.
"""

from __future__ import annotations

import multiprocessing
import os
import tempfile
import time
from typing import Any

import numpy as np

from patina.batch import Settings, run_batch
from patina.batch.render_tiles import render_on_dask
from patina.batch.scheduling import connect
from patina.bench.records import Record, median_times
from patina.bundled import materials_path
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides
from patina.synthetic.analytic import plastic, sample_isotropic
from patina.table import Brdf
from patina.table.formats import table_from_data

WORKERS = 2


def write_library(folder: str, tables: int) -> None:
    """`tables` plastics of different colours and roughness on a 10 x 10 x 13 isotropic grid."""
    theta = np.radians(np.linspace(0, 85, 10))
    phi = np.radians(np.linspace(0, 180, 13))
    os.makedirs(folder, exist_ok=True)
    for i in range(tables):
        hue = i / tables
        diffuse = (0.1 + 0.4 * hue, 0.4 - 0.3 * hue, 0.1 + 0.2 * (1 - hue))
        data = sample_isotropic(plastic(diffuse=diffuse, roughness=0.3 + 0.2 * hue), theta, theta, phi, "bench")
        Brdf(table_from_data(data), "synthetic").save(os.path.join(folder, f"plastic{i:02d}.ptab"))


def _library_record(one: Any, two: Any, repeat: int, quick: bool, ceiling: float) -> Record:
    """`ceiling`: the speedup of batch.machine.processes2, what 2 processes get here at all."""
    tables = 2 if quick else 8
    settings = Settings(
        steps=("validate", "fit") if quick else ("validate", "fit", "preview"),
        models=("ggx+lambert",),
        starts=1,
        width=96,
        height=72,
        spp=8,
    )
    with tempfile.TemporaryDirectory(prefix="patina-bench-batch-") as root:
        library = os.path.join(root, "library")
        write_library(library, tables)

        def run(client: Any) -> None:
            out = tempfile.mkdtemp(dir=root)  # a fresh folder: a rerun would skip the work
            run_batch(library, out, settings, client=client, progress=False, say=lambda line: None)

        t_one, t_two = median_times([lambda: run(one), lambda: run(two)], repeat)
    speedup = t_one / t_two
    preview = f", preview {settings.width}x{settings.height} {settings.spp} spp" if "preview" in settings.steps else ""
    return Record(
        "batch.library.workers2",
        f"patina batch of {tables} tables (validate, fit ggx+lambert{preview}) on {WORKERS} worker processes "
        f"({speedup / ceiling:.2f} of the {ceiling:.2f}x {WORKERS} processes get here); value = speedup / {WORKERS}",
        "the same batch on 1 worker process",
        speedup,
        speedup / WORKERS,
        "per worker",
    )


def _spin(n: int) -> int:
    """CPU work and nothing else (no memory traffic, no I/O): the machine's share of cores."""
    x = 0
    for i in range(n):
        x += i
    return x


def _ceiling_record(repeat: int, quick: bool) -> Record:
    """What 2 processes get from this machine at all: the same CPU-bound loop twice, in 2
    processes against one after the other. A shared machine that splits its cores between
    sessions (Linux's autogroup) gives one session's processes about a core in all, however
    many it runs: then no batch can reach 2x, and this record says so beside it."""
    n = 2_000_000 if quick else 20_000_000
    with multiprocessing.get_context("spawn").Pool(WORKERS) as pool:
        pool.map(_spin, [1] * WORKERS)  # the processes started before the timing
        serial, parallel = median_times(
            [lambda: [_spin(n) for _ in range(WORKERS)], lambda: pool.map(_spin, [n] * WORKERS)], repeat
        )
    speedup = serial / parallel
    return Record(
        "batch.machine.processes2",
        f"a CPU-bound loop in each of {WORKERS} processes (the ceiling this machine gives {WORKERS} workers); "
        f"value = speedup / {WORKERS}",
        "the same loops one after the other in one process",
        speedup,
        speedup / WORKERS,
        "per worker",
    )


def _render_record(client: Any, repeat: int, quick: bool) -> Record:
    w, h, spp = (64, 48, 4) if quick else (320, 240, 32)
    scene = with_overrides(load_scene(materials_path("scenes", "preview-ball.json")), width=w, height=h, spp=spp)
    prepared = PreparedScene(scene)
    t0 = time.perf_counter()
    render_on_dask(scene, client, prepared=prepared)  # ships the scene, prepares it on every worker
    cold = time.perf_counter() - t0
    local, tiles = median_times(
        [
            lambda: render(scene, threads=WORKERS, prepared=prepared),
            lambda: render_on_dask(scene, client, prepared=prepared),
        ],
        repeat,
    )
    return Record(
        "batch.render.tiles",
        f"preview-ball {w}x{h}, {spp} spp, path, as tiles on {WORKERS} worker processes (the first render, "
        f"shipping and preparing the scene: {cold:.2f} s); value = time overhead",
        f"the same render on {WORKERS} threads of this process",
        local / tiles,
        tiles / local - 1,
        "overhead",
    )


def bench_batch(repeat: int, quick: bool) -> list[Record]:
    """The `batch` group (none without Dask distributed)."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        print("patina bench: Dask distributed is not installed (pip install .[cluster]): no batch records")
        return []
    if quick:
        repeat = min(repeat, 3)  # a smoke test: whole batches and renders, each run counts
    ceiling = _ceiling_record(repeat, quick)
    with connect(None, 1) as (one, _), connect(None, WORKERS) as (two, _):
        return [_library_record(one, two, repeat, quick, ceiling.ratio), ceiling, _render_record(two, repeat, quick)]
