"""The `rgl` benchmark group: every record, finite and positive, in quick mode."""

from __future__ import annotations

import math

from patina.bench import GROUPS
from patina.bench.rgl import bench_rgl
from patina.native import _core


def test_quick_group_records():
    records = bench_rgl(1, quick=True)
    widths = [1] + [w for w in (4, 8, 16) if _core.width_supported(w)]
    expected = {f"brdf.eval.rgl.{kind}.w{w}" for kind in ("coherent", "random") for w in widths}
    assert {r.name for r in records} == expected | {"brdf.eval.rgl.vs_reference", "render.rgl.sampling_vs_cosine"}
    assert all(math.isfinite(r.ratio) and r.ratio > 0 and r.value > 0 for r in records)
    assert GROUPS["rgl"] is bench_rgl
    (sampling,) = [r for r in records if r.name == "render.rgl.sampling_vs_cosine"]
    assert sampling.ratio > 1  # the file's own warps beat the cosine even at the quick size
