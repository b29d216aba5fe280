"""The `cache` benchmark group run in quick mode with `path` standing in for the cache
integrators, and with a missing integrator (its records skipped with the reason); its sizes
(the scenes' own, `--large` twice that) and the `--large` run's record names."""

from __future__ import annotations

import math

import pytest

from patina.bench import GROUPS, Record
from patina.bench import cache as cb
from patina.bundled import materials_path
from patina.scene.reading import load_scene


def test_quick_group_with_path_standing_in_for_the_cache_integrators(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    stand_in = {"biased": "path", "guided": "path"}
    result = cb.run_cache_bench(1, quick=True, scenes=("cache-studio",), integrators=stand_in, mitsuba=False)
    names = {r.name for r in result.records}
    kinds = ("biased_vs_path", "bias", "bias_se", "block_steps", "flip_vs_path", "guided_vs_path", "guided_equal_time")
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
    # path against itself at (about) equal time: as good-looking, within the seeds' scatter
    flip = next(r for r in result.records if r.name.endswith(".flip_vs_path"))
    assert 0.5 < flip.ratio < 2.0 and 0 < flip.value < 1 and "equal time" in flip.baseline
    assert GROUPS["cache"] is cb.bench_cache


def test_the_full_sizes_are_the_scenes_own_and_large_twice_that():
    # the records measure where users render: the bench scenes' own width, and 384 with --large
    for name in cb.SCENES:
        assert load_scene(materials_path("scenes", f"{name}.json")).camera.width == cb.FULL.width == 192, name
    assert cb.LARGE.width == 2 * cb.FULL.width and "cache-car" in cb.SCENES


def test_a_large_run_names_its_records_apart(monkeypatch, capsys):
    # --large's records carry LARGE_SUFFIX, so they sit beside the default size's in one file
    found = cb.CacheBench([Record("cache.cache-car.bias", "c", "b", 1.0, 0.0, "%")], [("cache.threads", "why")])
    calls = []
    monkeypatch.setattr(cb, "run_cache_bench", lambda *a, **k: calls.append(k) or found)
    records = cb.bench_cache_large(7, False)
    assert [r.name for r in records] == ["cache.cache-car.bias.large"] and calls == [{"large": True}]
    assert "cache.threads.large skipped: why" in capsys.readouterr().err


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
        "cache.cache-studio.flip_vs_path",
        "cache.cache-studio.guided_vs_path",
        "cache.cache-studio.guided_equal_time",
        "cache.threads",
    }
    assert all("no-such-integrator" in why for _, why in result.skipped)
    assert not list(tmp_path.iterdir())  # nothing to compare: no reference rendered
