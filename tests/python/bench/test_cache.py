"""The `cache` benchmark group's harness: relMSE with the outliers discarded, error-versus-time
interpolation on log-log axes, the references kept on disk, and the group run in quick mode
with `path` standing in for the cache integrators (and with a missing integrator: skipped)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from patina.bench import GROUPS
from patina.bench import cache as cb
from patina.bundled import materials_path
from patina.scene.reading import load_scene


def test_relmse_is_the_relative_squared_error_with_the_top_tenth_of_a_percent_discarded():
    rng = np.random.default_rng(1)
    ref = rng.uniform(0.5, 2.0, (50, 40, 3))
    scale = ref.mean()
    image = ref * 1.1
    expected = (((0.1 * ref / scale) ** 2) / ((ref / scale) ** 2 + cb.RELMSE_EPSILON)).mean(axis=-1).ravel()
    # 2000 pixels: the 2 largest errors are discarded
    worst = np.sort(expected)
    assert cb.relmse(image, ref) == pytest.approx(worst[:-2].mean(), rel=1e-12)
    # a firefly among them does not count ...
    spiked = image.copy()
    spiked[3, 4] = 1e6
    assert cb.relmse(spiked, ref) == pytest.approx(worst[:-1].mean(), rel=1e-3)
    # ... and the measure does not depend on the image's brightness
    assert cb.relmse(image * 7, ref * 7) == pytest.approx(cb.relmse(image, ref), rel=1e-12)
    # the reference's own error is subtracted, never below zero
    assert cb.relmse(image, ref, reference_error=0.001) == pytest.approx(cb.relmse(image, ref) - 0.001)
    assert 0 < cb.relmse(image, ref, reference_error=1.0) < 1e-6
    assert cb.relmse(ref, ref) == 0


def test_error_curve_interpolates_and_extrapolates_on_log_log_axes():
    # Monte Carlo: error = c / time
    times = [0.5, 2.0, 8.0]
    curve = cb.ErrorCurve(times, [3.0 / t for t in times])
    assert curve.seconds_for(3.0 / 1.3) == pytest.approx(1.3)
    assert curve.seconds_for(3.0 / 40) == pytest.approx(40)  # beyond the ladder
    assert curve.seconds_for(3.0 / 0.1) == pytest.approx(0.1)
    assert curve.error_at(4.0) == pytest.approx(0.75)
    # a segment where the error went up (noise) counts as falling with slope -1
    noisy = cb.ErrorCurve([1.0, 2.0], [1.0, 1.2])
    assert noisy.error_at(4.0) == pytest.approx(1.0 / 4.0)
    with pytest.raises(ValueError):
        cb.ErrorCurve([1.0], [1.0])


def test_the_reference_is_rendered_once_and_kept(tmp_path):
    path = materials_path("scenes", "cache-studio.json")
    scene = cb._sized(load_scene(path), 8)
    first = cb.reference(path, scene, 8, threads=1, folder=str(tmp_path))
    again = cb.reference(path, scene, 8, threads=1, folder=str(tmp_path))
    assert first.rendered and not again.rendered
    assert np.array_equal(first.image, again.image) and first.error == again.error > 0
    other = cb.reference(path, scene, 16, threads=1, folder=str(tmp_path))
    assert other.rendered and other.path != first.path
    assert np.isfinite(first.image).all() and first.image.shape == (6, 8, 3)
    # a damaged file is rendered again
    with open(first.path, "wb") as f:
        f.write(b"not an npz")
    assert cb.reference(path, scene, 8, threads=1, folder=str(tmp_path)).rendered


def test_quick_group_with_path_standing_in_for_the_cache_integrators(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    stand_in = {"biased": "path", "guided": "path"}
    result = cb.run_cache_bench(1, quick=True, scenes=("cache-studio",), integrators=stand_in)
    names = {r.name for r in result.records}
    expected = {f"cache.cache-studio.{k}" for k in ("biased_vs_path", "bias", "guided_vs_path", "guided_equal_time")}
    assert names == expected | {"cache.threads"} and not result.skipped
    for r in result.records:
        assert math.isfinite(r.ratio) and r.ratio > 0 and math.isfinite(r.value), r
    bias = next(r for r in result.records if r.name.endswith(".bias"))
    assert bias.value == pytest.approx(100 * (bias.ratio - 1))
    assert GROUPS["cache"] is cb.bench_cache


def test_a_missing_integrator_skips_its_records_with_the_reason(tmp_path, monkeypatch):
    monkeypatch.setenv("PATINA_BENCH_CACHE", str(tmp_path))
    absent = {"biased": "no-such-integrator", "guided": "no-such-integrator"}
    result = cb.run_cache_bench(1, quick=True, scenes=("cache-studio",), integrators=absent)
    assert result.records == []
    assert {n for n, _ in result.skipped} == {
        "cache.cache-studio.biased_vs_path",
        "cache.cache-studio.bias",
        "cache.cache-studio.guided_vs_path",
        "cache.cache-studio.guided_equal_time",
        "cache.threads",
    }
    assert all("no-such-integrator" in why for _, why in result.skipped)
    assert not list(tmp_path.iterdir())  # nothing to compare: no reference rendered
