"""Grids by the standards' rules (patina.lighting.grids)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from patina.errors import FormatError
from patina.lighting.grids import Road, en12193_grids, en12464_cell, en12464_grid, en13201_points_along


def test_en12464_cell_size_follows_its_table():
    # EN 12464-1's table of p against d: 0.2 m at 1 m, 1 m at 10 m, 5 m at 100 m
    assert [round(en12464_cell(d), 6) for d in (1, 10, 100)] == [0.2, 1.0, 5.0]
    assert en12464_cell(1e4) == 10.0


@given(st.floats(0.5, 80), st.floats(0.5, 80))
def test_en12464_points_sit_at_centres_of_cells_no_larger_than_p(w, h):
    g = en12464_grid(0, 0, w, h, 0.8)
    p = en12464_cell(max(w, h))
    for c, length in ((g.x, w), (g.z, h)):
        step = length / len(c)
        assert step <= p * (1 + 1e-9)
        np.testing.assert_allclose(c, step * (np.arange(len(c)) + 0.5), atol=1e-9 * length)
    assert g.rule.startswith("EN 12464-1")


def test_the_wall_band_is_left_out_and_an_office_gets_its_grid():
    g = en12464_grid(0, 0, 6, 4, 0.75, wall_band=True)
    assert g.x[0] > 0.5 and g.x[-1] < 5.5 and g.z[0] > 0.5 and g.z[-1] < 3.5
    assert "wall band" in g.rule and g.y == 0.75
    with pytest.raises(FormatError, match="empty"):
        en12464_grid(0, 0, 0.8, 4, 0.75, wall_band=True)


@pytest.mark.parametrize(("spacing", "n"), [(30, 10), (12, 10), (31, 11), (45, 15), (45.1, 16)])
def test_en13201_points_along_the_field(spacing, n):
    assert en13201_points_along(spacing) == n
    assert spacing <= 30 or spacing / n <= 3


def test_en13201_field_lanes_and_observers():
    road = Road(x0=-3.5, lanes=2, lane_width=3.5, z0=0, spacing=30)
    g = road.luminance_grid()
    np.testing.assert_allclose(g.z, np.arange(10) * 3 + 1.5)  # D / 2 past the first luminaire
    np.testing.assert_allclose(g.x[:3], -3.5 + 3.5 / 3 * (np.arange(3) + 0.5))  # thirds' centres
    assert len(g.x) == 6
    e = road.illuminance_grid()
    assert len(e.x) == math.ceil(7 / 1.5) and np.diff(e.x).max() <= 1.5
    np.testing.assert_allclose(road.observers(), [[-1.75, 1.5, -60], [1.75, 1.5, -60]])


def test_en12193_principal_and_total_areas():
    pa, ta = en12193_grids(105, 68, 5, 5)
    assert pa.shape == (21, 14) and ta.shape == (23, 16)
    assert pa.x.min() > -34 and ta.x.min() < -34 and "PA" in pa.rule and "TA" in ta.rule
