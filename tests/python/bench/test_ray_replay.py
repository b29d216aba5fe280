"""The preview ball's recorded rays: recorded once, cached, replayed the same; the replay records."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest

from patina.bench import ray_replay
from patina.bench.records import simd_widths
from patina.bench.trace import _replay_records
from patina.geometry.accel import Accel


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_CACHE_DIR", str(tmp_path))
    return tmp_path


def test_records_then_replays_from_the_cache(cache):
    first = ray_replay.recorded_preview(quick=True)
    files = list((cache / "bench").glob("rays-preview-ball-*.npz"))
    assert len(files) == 1
    o, d = first.closest
    # camera rays (64 x 48 x 2 spp) and their bounces, and shadow rays
    assert len(o) > 64 * 48 * 2 and len(first.shadow[0]) > 0
    assert np.all(np.isfinite(o)) and np.all(np.linalg.norm(d, axis=1) > 0)
    # the recorded rays see the recorded geometry: most camera rays of the preview ball hit it
    hits = Accel(first.mesh).intersect(o, d)
    assert hits.hit.mean() > 0.2
    again = ray_replay.recorded_preview(quick=True)  # from the file this time
    assert np.array_equal(again.closest[0], o) and np.array_equal(again.shadow[2], first.shadow[2])
    assert np.array_equal(again.mesh.triangles(), first.mesh.triangles())


def test_replay_records(cache):
    records = _replay_records(1, quick=True)
    names = {r.name for r in records}
    expected = set()
    for w in simd_widths():
        expected |= {f"trace.replay.preview.path.p{w}_vs_scalar", f"trace.replay.preview.shadow.p{w}"}
        if importlib.util.find_spec("embreex"):
            expected |= {f"trace.replay.preview.path.p{w}_vs_embree", f"trace.replay.preview.shadow.p{w}_vs_embree"}
    if simd_widths():
        w = max(simd_widths())
        expected |= {f"trace.replay.preview.path.bvh_vs_p{w}", f"trace.replay.preview.shadow.bvh_vs_p{w}"}
        if importlib.util.find_spec("embreex"):
            expected |= {"trace.replay.preview.path.bvh_vs_embree", "trace.replay.preview.shadow.bvh_vs_embree"}
    assert expected <= names
    assert all(math.isfinite(r.ratio) and r.ratio > 0 and r.value > 0 for r in records)


def test_cache_dir_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.delenv("PATINA_CACHE_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert ray_replay.cache_dir() == tmp_path / "patina"
    monkeypatch.setenv("PATINA_CACHE_DIR", str(tmp_path / "x"))
    assert ray_replay.cache_dir() == tmp_path / "x"
