"""The `aa` benchmark group: every record per bundled aa-*.json scene, finite and positive,
in quick mode (at a quarter of the scenes' size, to keep the references cheap); the
references kept on disk are found again and not recomputed."""

from __future__ import annotations

import glob
import math
import os

import numpy as np
import pytest

from patina.bench import GROUPS, aa
from patina.bench.aa import bench_aa
from patina.bundled import materials_path
from patina.scene.reading import load_scene, with_overrides


def test_quick_group_records(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    monkeypatch.setattr(aa, "QUICK_FACTOR", 0.25)
    records = bench_aa(1, quick=True)
    scenes = [os.path.basename(p)[3:-5] for p in glob.glob(os.path.join(materials_path("scenes"), "aa-*.json"))]
    assert scenes
    kinds = {"rays_per_pixel", "vs_random25", "vs_stratified16", "vs_equal_rays", "time_vs_random25"}
    names = {r.name for r in records}
    for s in scenes:
        assert {f"aa.{s}.{k}" for k in kinds} <= names
    assert all(math.isfinite(r.ratio) and r.ratio > 0 and r.value > 0 for r in records)
    assert "aa" in GROUPS


def test_the_reference_is_kept_and_found_again(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    scene = with_overrides(load_scene(os.path.join(materials_path("scenes"), "aa-wires.json")), width=16, height=12)
    first = aa.reference(scene)
    assert first.shape == (12, 16, 3)
    assert len(os.listdir(aa.reference_dir())) == 1

    def no_render(*args, **kwargs):
        raise AssertionError("the kept reference was rendered again")

    monkeypatch.setattr(aa, "_stratified", no_render)
    assert np.array_equal(aa.reference(scene), first)
    # another size is another reference
    monkeypatch.undo()
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    aa.reference(with_overrides(scene, width=8, height=8))
    assert len(os.listdir(aa.reference_dir())) == 2


def test_a_bad_scale_is_one_line_and_exit_2(monkeypatch, capsys):
    monkeypatch.setenv(aa.SCALE_VARIABLE, "-1")
    with pytest.raises(SystemExit) as e:
        bench_aa(1, quick=True)
    assert e.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and aa.SCALE_VARIABLE in err
