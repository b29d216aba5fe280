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
from collections.abc import Callable
from dataclasses import asdict

from patina.atomic import write_text
from patina.bench.fit import bench_fit
from patina.bench.kernels import bench_brdf, bench_math
from patina.bench.lights import bench_lights
from patina.bench.records import Record
from patina.bench.render import bench_render
from patina.bench.trace import bench_trace
from patina.native import _core

GROUPS: dict[str, Callable[[int, bool], list[Record]]] = {
    "math": bench_math,
    "brdf": bench_brdf,
    "fit": bench_fit,
    "trace": bench_trace,
    "render": bench_render,
    "lights": bench_lights,
}


def print_table(records: list[Record]) -> None:
    print(f"{'name':<40} {'ratio':>7} {'value':>10}  {'unit':<12} candidate vs baseline")
    for r in records:
        print(f"{r.name:<40} {r.ratio:7.2f} {r.value:10.2f}  {r.unit:<12} {r.candidate} vs {r.baseline}")


def run_bench(only: str | None = None, json_path: str | None = None, repeat: int = 7, quick: bool = False) -> int:
    if only is not None and only not in GROUPS:
        print(f"patina bench: unknown group '{only}' (known: {', '.join(GROUPS)})", file=sys.stderr)
        return 2
    if repeat < 1:
        print("patina bench: --repeat must be at least 1", file=sys.stderr)
        return 2
    groups = [only] if only else list(GROUPS)
    records: list[Record] = []
    for g in groups:
        # brdf includes the math kernels it relies on, as the record list asks
        if g == "brdf" and only == "brdf":
            records += bench_math(repeat, quick)
        records += GROUPS[g](repeat, quick)
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
            "records": [asdict(r) for r in records],
        }
        write_text(json_path, json.dumps(doc, indent=2))
        print(f"wrote {json_path}")
    return 0
