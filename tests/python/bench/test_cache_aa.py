"""`cache.<scene>.aa_adaptive_vs_uniform` in quick mode: a finite positive time ratio, named
for its scene, with the error and time of both samplers in its text."""

from __future__ import annotations

import math

from patina.bench.cache_aa import aa_adaptive_record


def test_quick_record(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    record = aa_adaptive_record("cache-room", repeat=1, threads=2, quick=True)
    assert record.name == "cache.cache-room.aa_adaptive_vs_uniform"
    assert math.isfinite(record.ratio) and record.ratio > 0 and record.value > 0
    assert "adaptive antialiasing" in record.candidate and "uniform sampler" in record.baseline
    assert list(tmp_path.iterdir())  # the reference is kept where the cache group keeps its own
