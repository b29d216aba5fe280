"""The `fit` group: loss evaluation over a MERL-sized table at each width against width 1,
and the seconds a GGX + Lambert fit of that table takes on one thread."""

from __future__ import annotations

import functools
import time

import numpy as np

from patina.bench.records import Record, median_times, simd_widths
from patina.fitting import fit, table_samples
from patina.kernel_arrays import as_float32
from patina.native import _core
from patina.synthetic.analytic import merl_table
from patina.table.brdf import Brdf
from patina.table.formats import table_from_data


def bench_fit(repeat: int, quick: bool) -> list[Record]:
    """Loss evaluation over a MERL-sized table's samples at each width against width 1, and
    the seconds to fit GGX + Lambert to that table on one thread."""
    params = [0.3, 0.5, 0.2, 0.15, 0.04, 0.06, 0.08]

    def model(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        return _core.mixture_eval("ggx", params, as_float32(wi), as_float32(wo)).astype(np.float64)

    brdf = Brdf(table_from_data(merl_table(model)), "MERL-sized GGX + Lambert", "bench")
    samples = table_samples(brdf)
    if quick:
        samples = tuple(np.ascontiguousarray(a[:50_000]) for a in samples)
    fs = _core.FitSamples(*samples)
    n = fs.count
    records = []
    for w in simd_widths():
        t1, tw = median_times(
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
