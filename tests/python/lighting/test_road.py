"""Road luminance and EN 13201-3's figures (patina.lighting.road)."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from patina.errors import FormatError
from patina.lighting.direct import PlacedSource, direct_illuminance
from patina.lighting.grids import Road
from patina.lighting.road import (
    check_luminaires_for_ti,
    evaluate_road,
    road_luminance,
    threshold_increment,
    veiling_luminance,
)
from patina.lighting.rtable import read_rtable
from patina.lighting.sensors import Sensors
from patina.scene.types import PointLight
from repo_paths import ROOT

RTABLE = os.path.join(ROOT, "materials", "rtables", "synthetic-road.rtab")


def point(x, y, z, cd=1000.0):
    # 683 lm/W x Y of white (1, 1, 1) W/sr = cd
    return PlacedSource.of(PointLight((x, y, z), (cd / 683.0,) * 3))


def lambertian_table(tmp_path, q=0.07):
    tans = np.linspace(0, 12, 801)
    rows = "\n".join(f"{t:g} " + " ".join([f"{q * 1e4 * np.cos(np.arctan(t)) ** 3:.12g}"] * 2) for t in tans)
    path = tmp_path / "lambert.rtab"
    path.write_text("beta: 0 180\n" + rows + "\n")
    return read_rtable(path)


def test_a_lambertian_surface_has_luminance_q_times_illuminance_for_every_observer(tmp_path):
    table = lambertian_table(tmp_path)
    sources = [point(-3.5, 8, z) for z in (-30, 0, 30, 60)]
    pts = Road(-3.5, 2, 3.5, 0, 30).luminance_grid().points()
    e = direct_illuminance(sources, Sensors.horizontal(pts))
    for observer in ([-1.75, 1.5, -60], [1.75, 1.5, -60], [0, 1.5, 100]):
        np.testing.assert_allclose(road_luminance(sources, pts, np.array(observer, float), table), 0.07 * e, rtol=2e-3)


def test_beta_zero_is_the_luminaire_beyond_the_point_on_the_line_of_sight(tmp_path):
    path = tmp_path / "t.rtab"
    path.write_text("beta: 0 90 180\n0 100 100 100\n20 100 50 0\n")  # r falls with beta
    table = read_rtable(path)
    src = [point(0, 8, 20)]
    pts = np.array([[0.0, 0, 10]])
    ahead = road_luminance(src, pts, np.array([0, 1.5, -50.0]), table)  # light beyond the point
    behind = road_luminance(src, pts, np.array([0, 1.5, 60.0]), table)  # the observer past the light
    assert ahead[0] > behind[0] > 0
    # the beta 0 column is 100 x 10^-4 at every tan gamma: L = I r / H^2
    assert ahead[0] == pytest.approx(1000 * 100e-4 / 8**2, rel=1e-9)


def test_veiling_luminance_counts_only_luminaires_ahead_and_below_the_screening_plane():
    eye = np.array([0.0, 1.5, 0.0])
    far = point(0, 8, 60)  # 6.2 degrees up: counted
    steep = point(0, 8, 10)  # 33 degrees up: screened by the roof
    behind = point(0, 8, -30)
    lv = veiling_luminance([far, steep, behind], eye)
    d = np.array([0, 6.5, 60.0])
    sight = np.array([0, -math.sin(math.radians(1)), math.cos(math.radians(1))])
    cos_t = d @ sight / np.linalg.norm(d)
    theta = math.degrees(math.acos(cos_t))
    assert lv == pytest.approx(9.86 * 1000 * cos_t / (d @ d) / theta**2, rel=1e-9)


def test_ti_formula_changes_at_5_cd_m2():
    assert threshold_increment(0.2, 1.0) == pytest.approx(13.0)
    assert threshold_increment(0.2, 6.0) == pytest.approx(95 * 0.2 / 6.0**1.05)


def test_a_luminaire_below_the_eye_is_refused_for_ti():
    with pytest.raises(FormatError) as e:
        check_luminaires_for_ti("road.json", [point(0, 8, 0), point(0, 1.0, 30)], [0, 1])
    assert e.value.where == "lights[1]" and "TI" in e.value.problem


def test_the_bundled_table_gives_a_plausible_road():
    sources = [point(-3.5, 8, z, 8000) for z in range(-150, 211, 30)]
    r = evaluate_road(sources, Road(-3.5, 2, 3.5, 0, 30), read_rtable(RTABLE), maintenance=0.8, verge=3)
    f = r.figures()
    assert 0 < f["U0"] <= 1 and 0 < f["Ul"] <= 1 and f["TI"] > 0 and 0 < f["EIR"] < 2
    # L_av / E_av is about the surface's average coefficient Q0
    assert 0.5 * 0.0726 < f["L_av"] / f["E_av"] < 1.5 * 0.0726
