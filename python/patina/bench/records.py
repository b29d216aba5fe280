"""A benchmark record (name, candidate, baseline, ratio, value, unit; docs/bench.md) and the
timing every group uses: interleaved runs, medians, the SIMD widths to compare."""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from patina.native import _core
from patina.widths import WIDTHS


@dataclass
class Record:
    name: str
    candidate: str
    baseline: str
    ratio: float
    value: float
    unit: str


def median_times_and_values(fns: list[Callable[[], Any]], repeat: int) -> tuple[list[float], list[Any]]:
    """Median wall time of each function, runs interleaved so drift hits all alike, and the
    value each returned on its warm-up run (which also warms caches and pages in buffers)."""
    values = [f() for f in fns]
    samples: list[list[float]] = [[] for _ in fns]
    for _ in range(repeat):
        for i, f in enumerate(fns):
            t0 = time.perf_counter()
            f()
            samples[i].append(time.perf_counter() - t0)
    return [statistics.median(s) for s in samples], values


def median_times(fns: list[Callable[[], Any]], repeat: int) -> list[float]:
    return median_times_and_values(fns, repeat)[0]


def simd_widths() -> list[int]:
    """The wide paths this CPU runs, each compared with width 1 (records `.w4`, `.w8`, `.w16`)."""
    return [w for w in WIDTHS if w > 1 and _core.width_supported(w)]
