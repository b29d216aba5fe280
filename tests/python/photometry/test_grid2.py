"""The 2-D irregular-grid table (`_core.Grid2`, a goniometric light's candela table): the
coherent search and bilinear interpolation against scipy, knots reproduced exactly,
clamping outside the axes, widths 1/4/8 bit-identical, bad tables refused."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import RegularGridInterpolator

from conftest import WIDTHS
from patina.native import _core


def table(seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = np.unique(rng.uniform(0, 360, 17)).astype(np.float32)
    y = np.array([0, 2.5, 5, 10, 20, 35, 60, 90, 120, 150, 180], np.float32)  # dense near the axis
    return x, y, rng.uniform(0, 1000, (len(x), len(y))).astype(np.float32)


def test_interpolation_matches_scipy_and_knots_are_exact():
    x, y, v = table()
    g = _core.Grid2(x, y, v)
    rng = np.random.default_rng(1)
    qx = rng.uniform(x[0], x[-1], 20000).astype(np.float32)
    qy = rng.uniform(0, 180, 20000).astype(np.float32)
    ref = RegularGridInterpolator((x.astype(float), y.astype(float)), v.astype(float))(np.stack([qx, qy], -1))
    assert np.abs(g.eval(qx, qy) - ref).max() < 1e-6 * 1000
    ix, iy = np.meshgrid(np.arange(len(x)), np.arange(len(y)), indexing="ij")
    assert np.array_equal(g.eval(x[ix.ravel()], y[iy.ravel()]), v[ix.ravel(), iy.ravel()])


def test_outside_the_axes_clamps_to_the_ends():
    x, y, v = table()
    g = _core.Grid2(x, y, v)
    out = g.eval(np.array([x[0] - 50, x[-1] + 50], np.float32), np.array([-10, 400], np.float32))
    assert out[0] == v[0, 0] and out[1] == v[-1, -1]


def test_single_knot_axes_are_constant_along_them():
    g = _core.Grid2(np.array([0], np.float32), np.array([0, 90], np.float32), np.array([[10, 20]], np.float32))
    assert np.allclose(g.eval(np.array([0, 123], np.float32), np.array([45, 45], np.float32)), [15, 15])


def test_widths_are_bit_identical():
    x, y, v = table(2)
    g = _core.Grid2(x, y, v)
    rng = np.random.default_rng(3)
    qx = rng.uniform(-20, 380, 10007).astype(np.float32)
    qy = rng.uniform(-5, 185, 10007).astype(np.float32)
    ref = g.eval(qx, qy, width=1)
    for w in WIDTHS:
        assert np.array_equal(g.eval(qx, qy, width=w), ref)


@pytest.mark.parametrize("single_knot", [False, True])
def test_widths_are_bit_identical_where_the_lanes_share_cells(single_knot):
    # a packet's lanes in one cell (the corners broadcast), in neighbouring cells (the knots
    # picked from registers) and spread (gathered): sorted queries, slowly varying, with jumps
    x, y, v = table(4)
    if single_knot:
        x, v = x[:1], v[:1]
    g = _core.Grid2(x, y, v)
    rng = np.random.default_rng(5)
    qx = np.sort(rng.uniform(-20, 380, 4001)).astype(np.float32)
    qy = np.concatenate([np.full(1000, 3.0), np.linspace(0, 180, 2001), rng.uniform(-5, 185, 1000)]).astype(np.float32)
    ref = g.eval(qx, qy, width=1)
    for w in WIDTHS:
        assert np.array_equal(g.eval(qx, qy, width=w), ref)


@pytest.mark.parametrize(
    ("x", "y", "values", "problem"),
    [
        ([0, 0], [0, 1], [[1, 2], [3, 4]], "increase strictly"),
        ([0, 1], [0, np.nan], [[1, 2], [3, 4]], "not finite"),
        ([0, 1], [0, 1], [[1, 2, 3], [3, 4, 5]], "shape"),
        ([0, 1], [0, 1], [[1, np.inf], [3, 4]], "not finite"),
        ([], [0, 1], np.zeros((0, 2)), "at least one"),
    ],
)
def test_bad_tables_are_refused(x, y, values, problem):
    with pytest.raises(ValueError, match=problem):
        _core.Grid2(np.asarray(x, np.float32), np.asarray(y, np.float32), np.asarray(values, np.float32))
