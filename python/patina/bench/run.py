"""Running `patina bench`: kernel speed as ratios against a baseline measured in the same run.

Every record (docs/bench.md) has: name, candidate, baseline, ratio (baseline time /
candidate time, so > 1 means the candidate is faster), value and unit (the
candidate's absolute throughput). Single thread; candidate and baseline runs are
interleaved and each time is the median of `repeat` repetitions, which keeps the
ratio honest on a shared, noisy machine.
"""

from __future__ import annotations

import json
import os
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import asdict

from patina.atomic import check_writable, write_text
from patina.bench.aa import bench_aa
from patina.bench.batch import bench_batch
from patina.bench.cache import bench_cache, bench_cache_large
from patina.bench.fit import bench_fit
from patina.bench.kernels import bench_brdf, bench_math
from patina.bench.lighting import bench_lighting
from patina.bench.lights import bench_lights
from patina.bench.mitsuba_log import gathered_mitsuba_warnings
from patina.bench.profile import bench_profile
from patina.bench.records import Record
from patina.bench.render import bench_render
from patina.bench.rgl import bench_rgl
from patina.bench.trace import bench_trace
from patina.bundled import materials_path
from patina.native import _core
from patina.progress import Progress

GROUPS: dict[str, Callable[[int, bool], list[Record]]] = {
    "math": bench_math,
    "brdf": bench_brdf,
    "rgl": bench_rgl,
    "fit": bench_fit,
    "trace": bench_trace,
    "render": bench_render,
    "profile": bench_profile,
    "lights": bench_lights,
    "aa": bench_aa,
    "cache": bench_cache,
    "batch": bench_batch,
    "lighting": bench_lighting,
}
# `--large`: the groups with a larger size (their records named apart) in place of GROUPS'
LARGE_GROUPS: dict[str, Callable[[int, bool], list[Record]]] = {"cache": bench_cache_large}


def print_table(records: list[Record]) -> None:
    print(f"{'name':<40} {'ratio':>7} {'value':>10}  {'unit':<12} candidate vs baseline")
    for r in records:
        print(f"{r.name:<40} {r.ratio:7.2f} {r.value:10.2f}  {r.unit:<12} {r.candidate} vs {r.baseline}")


def _group_line(name: str, count: int, seconds: float, done: int, total: int, start: float) -> str:
    """One finished group, self-contained for a log: what, how long, done/total, time left (the
    mean time of the groups so far times those left; a rough guide, groups differ)."""
    elapsed = time.perf_counter() - start
    left = f", about {elapsed / done * (total - done):.0f} s left" if done < total else ""
    return f"bench: {name}: {count} records in {seconds:.1f} s ({done}/{total} groups done{left})"


def run_bench(
    only: str | None = None,
    json_path: str | None = None,
    repeat: int = 7,
    quick: bool = False,
    progress: bool = True,
    verbose: bool = False,
    large: bool = False,
) -> int:
    """Runs the groups (all, or `only`), prints the table, writes `json_path`. progress: a bar on
    stderr (a line every few seconds when it is not a terminal) and a line per finished group,
    since the whole run takes minutes. Mitsuba's warnings: one line at the end, or each once
    with `verbose` (bench/mitsuba_log.py). `large`: LARGE_GROUPS' larger sizes."""
    if only is not None and only not in GROUPS:
        print(f"patina bench: unknown group '{only}' (known: {', '.join(GROUPS)})", file=sys.stderr)
        return 2
    if repeat < 1:
        print("patina bench: --repeat must be at least 1", file=sys.stderr)
        return 2
    if large and (quick or (only is not None and only not in LARGE_GROUPS)):
        why = "--quick" if quick else f"group '{only}'"
        print(f"patina bench: --large does not apply to {why} (it sizes: {', '.join(LARGE_GROUPS)})", file=sys.stderr)
        return 2
    if json_path:
        check_writable(json_path)  # an OSError naming it now (exit 2), not after minutes of timing
    groups = [only] if only else list(GROUPS)
    if {"render", "profile", "lights", "aa", "cache", "batch", "lighting"} & set(groups):
        materials_path("scenes")  # their scenes are the checkout's: FileNotFoundError now, not minutes in
    # brdf includes the math kernels it relies on, as the record list asks
    chosen = {**GROUPS, **LARGE_GROUPS} if large else GROUPS
    steps = [("math", bench_math), ("brdf", bench_brdf)] if only == "brdf" else [(g, chosen[g]) for g in groups]
    records: list[Record] = []
    start = time.perf_counter()
    with gathered_mitsuba_warnings(verbose), Progress(len(steps), "bench", unit="group", enabled=progress) as bar:
        for done, (name, group) in enumerate(steps):
            bar.update(done, postfix=f"running {name}")
            t0 = time.perf_counter()
            found = group(repeat, quick)
            records += found
            if progress:  # tqdm writes even when the bar is disabled
                bar.write(_group_line(name, len(found), time.perf_counter() - t0, done + 1, len(steps), start))
        bar.update(len(steps), postfix="done")
    print_table(records)
    if json_path:
        doc = {
            "patina": _core.__version__,
            "machine": {
                "platform": platform.platform(),
                "processor": platform.processor(),
                "cpu_count": os.cpu_count(),
                "default_width": _core.default_width(),
            },
            "repeat": repeat,
            "quick": quick,
            "large": large,
            "records": [asdict(r) for r in records],
        }
        os.makedirs(os.path.dirname(os.path.abspath(json_path)), exist_ok=True)  # check_writable allowed it
        write_text(json_path, json.dumps(doc, indent=2))
        print(f"wrote {json_path}")
    return 0
