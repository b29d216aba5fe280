"""Indoor figures (patina.lighting.indoor): maintenance factor, Em / U0, CIE 117 UGR."""

from __future__ import annotations

import math

import numpy as np
import pytest

from patina.errors import FormatError
from patina.lighting.direct import PlacedSource
from patina.lighting.indoor import area_figures, maintenance_factor, position_index, ugr
from patina.scene.types import PointLight


def test_maintenance_factor_is_the_product_of_its_parts():
    assert maintenance_factor({"LLMF": 0.9, "LSF": 1.0, "LMF": 0.9, "RSMF": 0.95}, "p") == pytest.approx(0.7695)
    with pytest.raises(FormatError, match=r"maintenance\.LMF"):
        maintenance_factor({"LMF": 1.2}, "p")
    with pytest.raises(FormatError, match=r"maintenance\.XX"):
        maintenance_factor({"XX": 0.5}, "p")


def test_area_figures():
    f = area_figures(np.array([[400.0, 500], [600, 500]]))
    assert (f.em, f.e_min, f.e_max, f.u0) == (500, 400, 600, 0.8)


def test_position_index_is_one_on_the_line_of_sight_and_grows_off_it():
    assert position_index(0, 0) == 1
    p = position_index(np.array([10, 30, 60]), 0)
    assert np.all(np.diff(p) > 0)


def test_ugr_of_one_luminaire_by_hand():
    # 1000 cd towards the eye from 0.36 m^2 of horizontal luminous area, 2 m ahead, 1.5 m up
    src = PlacedSource.of(PointLight((2.0, 2.7, 0.0), (1000 / 683,) * 3))
    eye = np.array([0.0, 1.2, 0.0])
    value = ugr([src], [0.36], eye, 0.0, background=30.0)
    d = np.array([2.0, 1.5, 0.0])
    r = np.linalg.norm(d)
    projected = 0.36 * 1.5 / r
    sigma = math.degrees(math.atan2(1.5, 2.0))
    p = math.exp((35.2 - 1.22) * 1e-3 * sigma + 21e-5 * sigma**2)  # tau = 0: straight above the sight line
    expected = 8 * math.log10(0.25 / 30 * (1000 / projected) ** 2 * (projected / r**2) / p**2)
    assert value == pytest.approx(expected, rel=1e-9)
    # behind the observer: no glare
    assert ugr([src], [0.36], eye, 180.0, background=30.0) == -math.inf
