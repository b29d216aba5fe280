"""`patina bench`: kernel speed as ratios against a baseline measured in the same run.

Every record (docs/bench.md) has: name, candidate, baseline, ratio (baseline time /
candidate time, so > 1 means the candidate is faster), value and unit (the
candidate's absolute throughput). Single thread; candidate and baseline runs are
interleaved and each time is the median of `repeat` repetitions, which keeps the
ratio honest on a shared, noisy machine.
"""

from __future__ import annotations

import functools
import json
import os
import platform
import statistics
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from . import _core
from .atomic import write_text


@dataclass
class Record:
    name: str
    candidate: str
    baseline: str
    ratio: float
    value: float
    unit: str


def _median_times_and_values(fns: list[Callable[[], Any]], repeat: int) -> tuple[list[float], list[Any]]:
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


def _median_times(fns: list[Callable[[], Any]], repeat: int) -> list[float]:
    return _median_times_and_values(fns, repeat)[0]


def _widths() -> list[int]:
    return [w for w in (4, 8) if _core.width_supported(w)]


# --- inputs -----------------------------------------------------------------------------


def random_pairs(n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Independent uniformly distributed upper-hemisphere direction pairs."""
    rng = np.random.default_rng(seed)

    def hemi(k: int) -> np.ndarray:
        z = rng.uniform(0.0, 1.0, k)
        phi = rng.uniform(0.0, 2 * np.pi, k)
        r = np.sqrt(1 - z * z)
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)

    return hemi(n), hemi(n)


def coherent_pairs(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Pairs as neighbouring pixels produce them: a sphere seen from +z, lit from a fixed
    direction, scanned row by row; each pixel's light and view directions in its local frame."""
    side = int(np.ceil(np.sqrt(n / 0.7))) + 1
    u = (np.arange(side) + 0.5) / side * 2 - 1
    x, y = np.meshgrid(u, -u)
    inside = x * x + y * y < 0.999
    nrm = np.stack([x[inside], y[inside], np.sqrt(1 - x[inside] ** 2 - y[inside] ** 2)], axis=1)
    light = np.array([0.5, 0.6, 0.62])
    light /= np.linalg.norm(light)
    view = np.array([0.0, 0.0, 1.0])
    t = np.cross(nrm, [0.0, 1.0, 0.0])
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    b = np.cross(nrm, t)

    def local(w: np.ndarray) -> np.ndarray:
        return np.stack([t @ w, b @ w, nrm @ w], axis=1)

    wi, wo = local(light), local(view)
    lit = wi[:, 2] > 0.01
    wi, wo = wi[lit], wo[lit]
    reps = int(np.ceil(n / len(wi)))
    return (np.tile(wi, (reps, 1))[:n].astype(np.float32), np.tile(wo, (reps, 1))[:n].astype(np.float32))


def merl_sized_table() -> _core.Table:
    from .formats import table_from_data
    from .synthetic import merl_table, plastic

    return table_from_data(merl_table(plastic()))


def iso_table() -> _core.Table:
    """An irregular 30 x 30 x 60 isotropic table, denser near the specular direction."""
    from .formats import table_from_data
    from .synthetic import plastic, sample_isotropic

    theta = np.radians(89.0 * np.linspace(0, 1, 30) ** 1.2)
    u = np.linspace(0, 1, 60)
    phi = np.pi * (0.3 * u + 0.7 * np.sin(u * np.pi / 2))  # dense near phi_d = pi, where the peak lies
    return table_from_data(sample_isotropic(plastic(), theta, theta, phi, "bench"))


# --- groups -----------------------------------------------------------------------------


def bench_math(repeat: int, quick: bool) -> list[Record]:
    n = 1 << (14 if quick else 20)
    rng = np.random.default_rng(3)
    x = rng.uniform(-1, 1, n).astype(np.float32)
    y = rng.normal(size=n).astype(np.float32)
    records = []
    for op, libc, args in (("acos", "libc_acos", (x,)), ("atan2", "libc_atan2", (y, x))):
        out = np.empty(n, np.float32)
        for w in _widths():
            base = functools.partial(_core.math, libc, *args, width=1, out=out)
            cand = functools.partial(_core.math, op, *args, width=w, out=out)
            tb, tc = _median_times([base, cand], repeat)
            records.append(
                Record(
                    f"math.{op}.w{w}",
                    f"fast_{op} width {w}",
                    f"C library {op}f, scalar",
                    tb / tc,
                    n / tc / 1e6,
                    "Mvalues/s",
                )
            )
    return records


def bench_brdf(repeat: int, quick: bool) -> list[Record]:
    n = 1 << (13 if quick else 18)
    records: list[Record] = []
    merl = merl_sized_table()
    iso = iso_table()
    rnd = random_pairs(n)
    coh = coherent_pairs(n)

    # coherent binary search alone, on the theta_h axis of the MERL table (90 irregular knots),
    # with the coordinates the two direction sets produce.
    knots = np.ascontiguousarray(merl.axes[0])
    for label, (wi, wo) in (("", coh), (".random", rnd)):
        h = wi + wo
        th = np.arccos(np.clip(h[:, 2] / np.linalg.norm(h, axis=1), -1, 1)).astype(np.float32)
        cells = np.empty(n, np.int32)
        for w in _widths():
            scalar = functools.partial(_core.search, knots, th, width=1, out=cells)
            masked = functools.partial(_core.search, knots, th, width=w, out=cells)
            thesis = functools.partial(_core.search, knots, th, width=w, out=cells, split="sequential")
            tb, tc, tt = _median_times([scalar, masked, thesis], repeat)
            records.append(
                Record(
                    f"brdf.search{label}.w{w}",
                    f"coherent search width {w}",
                    "binary search width 1",
                    tb / tc,
                    n / tc / 1e6,
                    "Msearches/s",
                )
            )
            records.append(
                Record(
                    f"brdf.search{label}.thesis.w{w}",
                    f"coherent search width {w}, sequential split walk (thesis)",
                    "binary search width 1",
                    tb / tt,
                    n / tt / 1e6,
                    "Msearches/s",
                )
            )

    for tname, table in (("merl", merl), ("iso", iso)):
        for dname, (wi, wo) in (("random", rnd), ("coherent", coh)):
            t1 = None
            out = np.empty((n, table.channels), np.float32)
            for w in _widths():
                tb, tc = _median_times(
                    [
                        functools.partial(table.eval, wi, wo, width=1, threads=1, out=out),
                        functools.partial(table.eval, wi, wo, width=w, threads=1, out=out),
                    ],
                    repeat,
                )
                t1 = tb if t1 is None else min(t1, tb)
                records.append(
                    Record(
                        f"brdf.eval.{tname}.{dname}.w{w}",
                        f"evaluator width {w}",
                        "evaluator width 1",
                        tb / tc,
                        n / tc / 1e6,
                        "Mevals/s",
                    )
                )
            if t1 is not None:
                records.append(
                    Record(
                        f"brdf.eval.{tname}.{dname}.w1",
                        "evaluator width 1",
                        "evaluator width 1",
                        1.0,
                        n / t1 / 1e6,
                        "Mevals/s",
                    )
                )
            # against a plain scalar evaluator using the C library's acosf / atan2f
            for w in _widths():
                tb, tc = _median_times(
                    [
                        functools.partial(table.eval, wi, wo, width=1, threads=1, out=out, libm_trig=True),
                        functools.partial(table.eval, wi, wo, width=w, threads=1, out=out),
                    ],
                    repeat,
                )
                records.append(
                    Record(
                        f"brdf.eval.{tname}.{dname}.w{w}_vs_libm",
                        f"evaluator width {w}",
                        "scalar evaluator with C library acosf/atan2f",
                        tb / tc,
                        n / tc / 1e6,
                        "Mevals/s",
                    )
                )
    return records


def bench_fit(repeat: int, quick: bool) -> list[Record]:
    """Loss evaluation over a MERL-sized table's samples at each width against width 1, and
    the seconds to fit GGX + Lambert to that table on one thread."""
    from .fitting import fit, table_samples
    from .formats import table_from_data
    from .synthetic import merl_table

    params = [0.3, 0.5, 0.2, 0.15, 0.04, 0.06, 0.08]

    def model(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        as32 = functools.partial(np.ascontiguousarray, dtype=np.float32)
        return _core.mixture_eval("ggx", params, as32(wi), as32(wo)).astype(np.float64)

    from .brdf import Brdf

    brdf = Brdf(table_from_data(merl_table(model)), "MERL-sized GGX + Lambert", "bench")
    samples = table_samples(brdf)
    if quick:
        samples = tuple(np.ascontiguousarray(a[:50_000]) for a in samples)
    fs = _core.FitSamples(*samples)
    n = fs.count
    records = []
    for w in _widths():
        t1, tw = _median_times(
            [
                functools.partial(fs.mixture_loss, "ggx", params, "l2cos", 1, 1),
                functools.partial(fs.mixture_loss, "ggx", params, "l2cos", w, 1),
            ],
            repeat,
        )
        records.append(
            Record(
                f"fit.loss.w{w}",
                f"l2cos loss, lobes at width {w}",
                "the same at width 1",
                t1 / tw,
                n / tw / 1e6,
                "Msamples/s",
            )
        )
    if not quick:
        start = time.perf_counter()
        result = fit(brdf, threads=1)
        seconds = time.perf_counter() - start
        records.append(
            Record(
                "fit.time.ggx_lambert", f"fit GGX + Lambert, {result.samples} samples, 1 thread", "", 1.0, seconds, "s"
            )
        )
    return records


def bench_trace(repeat: int, quick: bool) -> list[Record]:
    # imported late: bench_trace builds on Record and _median_times from this module
    from .bench_trace import bench_trace as run

    return run(repeat, quick)


def bench_render(repeat: int, quick: bool) -> list[Record]:
    from .bench_render import run_render_group

    return run_render_group(repeat, quick)


def bench_lights(repeat: int, quick: bool) -> list[Record]:
    from .bench_lights import run_lights_group

    return run_lights_group(repeat, quick)


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
