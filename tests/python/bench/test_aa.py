"""The `aa` benchmark group: every record per bundled aa-*.json scene, finite and positive,
in quick mode."""

from __future__ import annotations

import glob
import math
import os

from patina.bench import GROUPS
from patina.bench.aa import bench_aa
from patina.bundled import materials_path


def test_quick_group_records():
    records = bench_aa(1, quick=True)
    scenes = [os.path.basename(p)[3:-5] for p in glob.glob(os.path.join(materials_path("scenes"), "aa-*.json"))]
    assert scenes
    kinds = {"rays_per_pixel", "vs_random25", "vs_stratified16", "vs_equal_rays", "time_vs_random25"}
    names = {r.name for r in records}
    for s in scenes:
        assert {f"aa.{s}.{k}" for k in kinds} <= names
    assert all(math.isfinite(r.ratio) and r.ratio > 0 and r.value > 0 for r in records)
    assert "aa" in GROUPS
