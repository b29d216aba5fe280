"""The `lights` benchmark group: every record, finite and positive, in quick mode."""

from __future__ import annotations

import math

from patina import _core
from patina.bench import GROUPS
from patina.bench_lights import run_lights_group


def test_quick_group_records():
    records = run_lights_group(1, quick=True)
    names = {r.name for r in records}
    widths = [w for w in (4, 8) if _core.width_supported(w)]
    assert names == {f"lights.sample.{k}.w{w}" for k in ("goniometric", "area", "environment") for w in widths}
    assert all(math.isfinite(r.ratio) and r.ratio > 0 and r.value > 0 for r in records)
    assert "lights" in GROUPS
