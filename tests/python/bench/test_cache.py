"""The `cache` benchmark group run in quick mode with `path` standing in for the cache
integrators, and with a missing integrator (its records skipped with the reason)."""

from __future__ import annotations

import math

import pytest

from patina.bench import GROUPS
from patina.bench import cache as cb


def test_quick_group_with_path_standing_in_for_the_cache_integrators(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    stand_in = {"biased": "path", "guided": "path"}
    result = cb.run_cache_bench(1, quick=True, scenes=("cache-studio",), integrators=stand_in, mitsuba=False)
    names = {r.name for r in result.records}
    kinds = ("biased_vs_path", "bias", "bias_se", "block_steps", "guided_vs_path", "guided_equal_time")
    expected = {f"cache.cache-studio.{k}" for k in kinds}
    assert names == expected | {"cache.threads"} and not result.skipped
    for r in result.records:
        assert math.isfinite(r.ratio) and r.ratio > 0 and math.isfinite(r.value), r
    bias = next(r for r in result.records if r.name.endswith(".bias"))
    assert bias.value == pytest.approx(100 * (bias.ratio - 1))
    # the bias is the mean over BIAS_SEEDS seeds, its standard error beside it (path standing
    # in for cache: unbiased, so within a few standard errors of zero)
    se = next(r for r in result.records if r.name.endswith(".bias_se"))
    assert se.value == pytest.approx(100 * se.ratio) and f"mean over {cb.BIAS_SEEDS} seeds" in bias.candidate
    assert abs(bias.value) < 4 * se.value + 1.0
    assert GROUPS["cache"] is cb.bench_cache


def test_a_missing_integrator_skips_its_records_with_the_reason(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    absent = {"biased": "no-such-integrator", "guided": "no-such-integrator"}
    result = cb.run_cache_bench(1, quick=True, scenes=("cache-studio",), integrators=absent, mitsuba=False)
    assert result.records == []
    assert {n for n, _ in result.skipped} == {
        "cache.cache-studio.biased_vs_path",
        "cache.cache-studio.bias",
        "cache.cache-studio.bias_se",
        "cache.cache-studio.block_steps",
        "cache.cache-studio.guided_vs_path",
        "cache.cache-studio.guided_equal_time",
        "cache.threads",
    }
    assert all("no-such-integrator" in why for _, why in result.skipped)
    assert not list(tmp_path.iterdir())  # nothing to compare: no reference rendered
