"""The `render` benchmark group: its records in quick mode, the measured error curve behind
render.vs_mitsuba and render.preview.vs_mitsuba_llvm recovering a known noise level, and the
error-versus-time interpolation behind both."""

from __future__ import annotations

import math
import os
from types import SimpleNamespace

import numpy as np
import pytest

from patina.bench import GROUPS, Record, records
from patina.bench.render import _error_curve, _seconds_to_error, _spp_to_target, bench_render
from patina.native import _core


def test_quick_group_records():
    pytest.importorskip("mitsuba")
    records = bench_render(1, quick=True)
    assert all(isinstance(r, Record) for r in records)
    by_name = {r.name: r for r in records}
    expected = {f"render.preview.w{w}" for w in (4, 8, 16) if _core.width_supported(w)}
    expected |= {"render.threads", "render.vs_mitsuba", "render.preview.ld_vs_independent"}
    expected.add("render.preview.bvh_vs_kdtree")
    # the llvm records only where Mitsuba's llvm_ad_rgb runs
    llvm = {"render.vs_mitsuba_llvm", "render.vs_mitsuba_llvm.triangles", "render.preview.vs_mitsuba_llvm"}
    assert expected <= set(by_name) <= expected | llvm
    if "render.vs_mitsuba_llvm" in by_name:
        assert llvm <= set(by_name)
        assert all(by_name[name].unit == "s" for name in llvm)
    for r in records:
        assert math.isfinite(r.ratio) and r.ratio > 0, r
        assert math.isfinite(r.value) and r.value > 0, r
    threads = by_name["render.threads"]
    assert threads.value == pytest.approx(threads.ratio / (os.cpu_count() or 1))
    assert by_name["render.vs_mitsuba"].unit == "s"
    assert by_name["render.preview.ld_vs_independent"].unit == "spp"
    assert GROUPS["render"].__name__ == "bench_render"


def test_error_curve_is_net_of_the_references_noise(monkeypatch):
    """A fake renderer whose pixels carry noise of standard deviation sigma / sqrt(spp): the
    curve behind render.vs_mitsuba and render.preview.vs_mitsuba_llvm gives each level's
    relative MSE (sigma / mean)^2 / spp net of the reference's own noise, and its time (1 ms a
    sample here, on a fake clock: slept time on a loaded machine overshoots)."""
    rng = np.random.default_rng(7)
    truth = rng.uniform(0.5, 1.5, (96, 128, 3))
    sigma, ref_spp = 0.8, 4096

    def noisy(spp: int) -> np.ndarray:
        return truth + rng.normal(0, sigma / math.sqrt(spp), truth.shape)

    clock = [0.0]
    monkeypatch.setattr(records, "time", SimpleNamespace(perf_counter=lambda: clock[0]))

    def render_at(spp: int) -> np.ndarray:
        clock[0] += 1e-3 * spp
        return noisy(spp)

    a, b = noisy(ref_spp // 2), noisy(ref_spp // 2)
    reference, reference_mse = (a + b) / 2, float(((a - b) ** 2).mean()) / 4
    levels = [16, 64, 256]
    curve = _error_curve(render_at, levels, reference, reference_mse, repeat=3)
    for n, (t, mse) in zip(levels, curve):
        assert mse == pytest.approx((sigma / truth.mean()) ** 2 / n, rel=0.05)
        assert t == pytest.approx(1e-3 * n, rel=1e-9)


@pytest.mark.parametrize("exponent", [1.0, 1.3])
def test_seconds_to_error_follows_the_measured_power_law(exponent):
    """MSE = 0.5 t^-exponent measured at 1, 4 and 16 s: the time for an error between two of
    them, or beyond them, is the power law's (exact here), whichever way the points are given."""
    curve = [(t, 0.5 * t**-exponent) for t in (16.0, 1.0, 4.0)]
    for t in (2.0, 9.0, 40.0, 0.5):
        assert _seconds_to_error(curve, 0.5 * t**-exponent) == pytest.approx(t, rel=1e-9)
    # an error that does not fall (noise): the later point's time
    assert _seconds_to_error([(1.0, 0.1), (2.0, 0.1), (4.0, 0.2)], 0.01) == 4.0


@pytest.mark.parametrize("exponent", [1.0, 1.5])
def test_spp_to_target_follows_the_measured_power_law(exponent):
    """MSE = 0.3 spp^-exponent: the levels 16, 64, ... until the target, and the spp at which
    the power law through the last two meets it (exact here); a target never reached stops
    at the last level and extrapolates."""
    measured = []

    def mse_at(spp: int) -> float:
        measured.append(spp)
        return 0.3 * spp**-exponent

    target = 0.3 * 700.0**-exponent
    spp, levels = _spp_to_target(mse_at, target, 16, 4096)
    assert spp == pytest.approx(700.0, rel=1e-9)
    assert [n for n, _ in levels] == measured == [16, 64, 256, 1024]
    far, levels = _spp_to_target(mse_at, 0.3 * 1e5**-exponent, 16, 256)
    assert far == pytest.approx(1e5, rel=1e-9) and [n for n, _ in levels] == [16, 64, 256]
