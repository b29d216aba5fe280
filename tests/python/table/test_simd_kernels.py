"""The SIMD kernels through Python: every width equals width 1 lane for lane, any length."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import WIDTHS
from patina.native import _core

SPECIALS = np.array([0.0, -0.0, 1.0, -1.0, np.inf, -np.inf, np.nan, 1e-40, -1e-40, 0.5, 2.0], np.float32)


@pytest.mark.parametrize("op", ["acos", "asin", "atan", "sqrt"])
@pytest.mark.parametrize("n", [1, 3, 4, 7, 8, 9, 1001])
def test_unary_ops_equal_width_1(op, n):
    rng = np.random.default_rng(n)
    x = np.concatenate([rng.uniform(-1.2, 1.2, n), SPECIALS]).astype(np.float32)
    want = _core.math(op, x, width=1)
    for w in WIDTHS:
        np.testing.assert_array_equal(_core.math(op, x, width=w), want)


def test_atan2_equals_width_1_and_matches_numpy():
    rng = np.random.default_rng(2)
    y = np.concatenate([rng.normal(size=5003), np.repeat(SPECIALS, SPECIALS.size)]).astype(np.float32)
    x = np.concatenate([rng.normal(size=5003), np.tile(SPECIALS, SPECIALS.size)]).astype(np.float32)
    want = _core.math("atan2", y, x, width=1)
    for w in WIDTHS:
        np.testing.assert_array_equal(_core.math("atan2", y, x, width=w), want)
    ref = np.arctan2(y.astype(np.float64), x.astype(np.float64))
    assert np.nanmax(np.abs(want - ref)) <= 5e-7
    np.testing.assert_array_equal(np.isnan(want), np.isnan(ref))


def test_search_matches_searchsorted():
    knots = np.cumsum(np.random.default_rng(3).uniform(0.01, 0.2, 90)).astype(np.float32)
    x = np.concatenate([np.random.default_rng(4).uniform(-1, knots[-1] + 1, 10001), knots, [np.nan]]).astype(np.float32)
    want = np.clip(np.searchsorted(knots, x, side="right") - 1, 0, knots.size - 2)
    want[np.isnan(x)] = 0
    for w in WIDTHS:
        np.testing.assert_array_equal(_core.search(knots, x, width=w), want)
        np.testing.assert_array_equal(_core.search(knots, x, width=w, split="sequential"), want)
    with pytest.raises(ValueError, match="increasing"):
        _core.search(knots[::-1].copy(), x)


def test_patina_simd_environment_variable():
    import subprocess
    import sys

    code = "from patina import _core; print(_core.default_width())"
    for value, width in (("scalar", 1), ("sse4", 4), ("avx2", 8)):
        if not _core.width_supported(width):
            continue
        r = subprocess.run(
            [sys.executable, "-c", code],
            check=False,
            capture_output=True,
            text=True,
            env={"PATINA_SIMD": value, "PATH": "/usr/bin:/bin"},
        )
        assert r.returncode == 0 and r.stdout.strip() == str(width), r.stderr
    r = subprocess.run(
        [sys.executable, "-c", code],
        check=False,
        capture_output=True,
        text=True,
        env={"PATINA_SIMD": "neon", "PATH": "/usr/bin:/bin"},
    )
    assert r.returncode != 0 and "PATINA_SIMD=neon" in r.stderr
