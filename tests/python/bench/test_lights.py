"""The `lights` benchmark group: every record, finite and positive, in quick mode."""

from __future__ import annotations

import math

from patina.bench import GROUPS
from patina.bench.lights import bench_lights
from patina.native import _core


def test_quick_group_records():
    records = bench_lights(1, quick=True)
    names = {r.name for r in records}
    widths = [w for w in (4, 8, 16) if _core.width_supported(w)]
    assert names == {f"lights.sample.{k}.w{w}" for k in ("goniometric", "area", "environment") for w in widths}
    assert all(math.isfinite(r.ratio) and r.ratio > 0 and r.value > 0 for r in records)
    assert "lights" in GROUPS
