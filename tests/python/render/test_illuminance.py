"""`patina illuminance`: direct illuminance on a sensor grid against I cos / d^2 and a disc's
form factor, uniformity ratios, outputs, bad grids."""

from __future__ import annotations

import json
import math
import os

import numpy as np
import pytest

from conftest import WIDTHS
from patina.cli import main
from patina.errors import FormatError
from patina.render import illuminance as il
from patina.scene.reading import load_scene, parse_scene
from repo_paths import ROOT

STREET = os.path.join(ROOT, "materials", "scenes", "street-luminaire.json")


def scene(lights: list) -> object:
    obj = {
        "version": 1,
        "camera": {"position": [0, 5, 5], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "materials": {"m": {"type": "lambert", "albedo": 0.5}},
        "shapes": [{"type": "plane", "material": "m", "size": [40, 40]}],
        "lights": lights,
    }
    return parse_scene(obj, os.path.join(ROOT, "sensors.json"))


def test_point_light_illuminance_is_exact_at_every_sensor_and_width():
    s = scene([{"type": "point", "position": [1, 2.5, -0.5], "intensity_cd": 1000}])
    grid = il.parse_grid("-3,-3,3,3,13,13", height=0.0)
    _, _, pts = grid.points()
    to = np.array([1, 2.5, -0.5]) - pts
    d2 = (to**2).sum(1)
    expected = 1000 * (to[:, 1] / np.sqrt(d2)) / d2
    for width in WIDTHS:
        report = il.compute(s, grid, samples=4, width=width)
        assert np.allclose(report.lux.ravel(), expected, rtol=2e-5)
    st = report.stats
    assert st["u0"] == pytest.approx(expected.min() / expected.mean(), rel=1e-4)
    assert st["ud"] == pytest.approx(expected.min() / expected.max(), rel=1e-4)


def test_disk_light_illuminance_matches_the_form_factor_at_1_percent():
    # 1M samples in all: 4096 sensors x 256 light samples
    s = scene([{"type": "disk", "center": [0, 2, 0], "normal": [0, -1, 0], "radius": 0.5, "luminance": 1000}])
    grid = il.parse_grid("-2,-2,2,2,64,64", height=0.0)
    report = il.compute(s, grid, samples=256)
    _, _, pts = grid.points()
    rho2 = pts[:, 0] ** 2 + pts[:, 2] ** 2
    a = 4 + rho2
    ff = 0.5 * (1 - (a - 0.25) / np.sqrt((a + 0.25) ** 2 - 4 * 0.25 * rho2))  # disc to a parallel element
    expected = math.pi * 1000 * ff  # lux: pi L F with L in cd/m^2
    assert abs(report.lux.mean() / expected.mean() - 1) < 0.01


def test_cli_prints_a_report_and_writes_csv_json_and_png(tmp_path, capsys):
    args = [
        "illuminance",
        STREET,
        "--grid=-3.5,-15,3.5,15,8,31",
        "--samples",
        "16",
        "--csv",
        str(tmp_path / "e.csv"),
        "--json-out",
        str(tmp_path / "e.json"),
        "--png",
        str(tmp_path / "e.png"),
    ]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "Emin" in out and "U0 = Emin / Eavg" in out
    rows = (tmp_path / "e.csv").read_text().splitlines()
    assert rows[0] == "x,y,z,lux" and len(rows) == 1 + 8 * 31
    doc = json.loads((tmp_path / "e.json").read_text())
    assert doc["grid"]["nx"] == 8 and 0 < doc["min_lux"] <= doc["mean_lux"] <= doc["max_lux"]
    assert np.asarray(doc["lux"]).shape == (31, 8)
    assert (tmp_path / "e.png").stat().st_size > 1000
    assert sorted(os.listdir(tmp_path)) == ["e.csv", "e.json", "e.png"]


@pytest.mark.parametrize("spec", ["1,2,3", "a,b,c,d,1,1", "0,0,1,1,0,5", "0,0,1,1,5,99999", "nan,0,1,1,2,2"])
def test_bad_grids_are_refused_with_the_option_named(spec, capsys):
    with pytest.raises(FormatError, match="--grid"):
        il.parse_grid(spec)
    assert main(["illuminance", STREET, f"--grid={spec}"]) == 2
    err = capsys.readouterr().err
    assert "--grid" in err and "Traceback" not in err


@pytest.mark.parametrize("form", [["--grid", "-3.5,-15,3.5,15,4,5"], ["--grid=-3.5,-15,3.5,15,4,5"]])
def test_a_grid_with_negative_corners_is_accepted_in_both_forms(capsys, form):
    # argparse took '-3.5,...' for an option ("expected one argument") unless written --grid=
    assert main(["illuminance", STREET, *form, "--samples", "4", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["grid"]["x0"] == -3.5 and report["grid"]["z0"] == -15 and report["grid"]["nz"] == 5


def test_illuminance_refuses_existing_outputs_without_force_before_computing(tmp_path, capsys):
    csv_path = tmp_path / "lux.csv"
    csv_path.write_text("keep me")
    args = ["illuminance", STREET, "--grid", "-1,-1,1,1,2,2", "--samples", "4", "--csv", str(csv_path)]
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.err.strip() == f"patina: error: {csv_path}: exists; pass --force to overwrite it"
    assert captured.out == "" and csv_path.read_text() == "keep me"
    assert main([*args, "--force"]) == 0
    assert csv_path.read_text().startswith("x,y,z,lux")


@pytest.mark.parametrize(("option", "value"), [("--samples", "0"), ("--samples", "99999999999"), ("--png", "x.jpg")])
def test_bad_illuminance_options_exit_2_naming_the_option(tmp_path, monkeypatch, capsys, option, value):
    monkeypatch.chdir(tmp_path)
    assert main(["illuminance", STREET, "--grid", "-1,-1,1,1,2,2", option, value]) == 2
    err = capsys.readouterr().err
    assert option in err and len(err.strip().splitlines()) == 1 and os.listdir(tmp_path) == []


def test_a_grid_larger_than_a_chunk_is_computed_in_chunks_with_progress(monkeypatch, capsys):
    s = scene([{"type": "point", "position": [1, 2.5, -0.5], "intensity_cd": 1000}])
    grid = il.parse_grid("-3,-3,3,3,13,13", height=0.0)
    whole = il.compute(s, grid, samples=4).lux
    assert capsys.readouterr().err == ""  # one chunk: no progress display
    monkeypatch.setattr(il, "CHUNK_SENSORS", 7)  # 169 sensors: 25 chunks, the last of 1
    chunked = il.compute(s, grid, samples=4, progress=True).lux
    np.testing.assert_allclose(chunked, whole, rtol=1e-6)  # a point light has no noise
    err = capsys.readouterr().err
    assert "illuminance" in err and "169/169" in err


def test_vertical_and_cylindrical_sensors_from_a_point_light(capsys):
    s = scene([{"type": "point", "position": [0, 3, 4], "intensity_cd": 1000}])
    grid = il.parse_grid("0,0,0,0,1,1", height=1.0)
    to = np.array([0.0, 2.0, 4.0])
    d2 = to @ to
    sin_eps, cos_face = 4 / math.sqrt(d2), 4 / math.sqrt(d2)  # horizontal part; facing +z (azimuth 90)
    cases = {
        "vertical:90": 1000 / d2 * cos_face,
        "vertical:270": 0.0,
        "cylindrical": 1000 / d2 * sin_eps / math.pi,
        "semicylindrical:90": 1000 / d2 * sin_eps * 2 / math.pi,
        "semicylindrical:0": 1000 / d2 * sin_eps / math.pi,
    }
    for spec, expected in cases.items():
        report = il.compute(s, grid, samples=1, sensor=spec)
        assert report.lux[0, 0] == pytest.approx(expected, rel=1e-6, abs=1e-9), spec
        assert report.as_json()["sensor"] == spec
    assert main(["illuminance", STREET, "--grid=-3.5,-15,3.5,15,4,4", "--sensor", "cylindrical"]) == 2
    assert "(--sensor): cylindrical sensors sum point, spot and goniometric luminaires only" in capsys.readouterr().err
    assert main(["illuminance", STREET, "--grid=-3.5,-15,3.5,15,4,4", "--sensor", "vertical:north"]) == 2
    assert "(--sensor): expected up, down, vertical:AZ" in capsys.readouterr().err


def test_indirect_from_the_radiance_cache_agrees_with_the_sensor_paths(capsys):
    office = os.path.join(ROOT, "materials", "scenes", "office-en12464.json")
    s = load_scene(office)
    grid = il.parse_grid("-2.8,-1.8,2.8,1.8,15,10", height=0.75)
    direct = il.compute(s, grid, samples=4).lux
    cached = il.compute(s, grid, samples=4, indirect=True, indirect_cache=True).lux - direct
    traced = il.compute(s, grid, samples=1024, indirect=True).lux - direct
    assert np.all(cached > 0)
    # the interreflections: the bias docs/lighting.md measures (+0.5 %) and both estimates' noise
    assert abs(cached.mean() / traced.mean() - 1) < 0.03
    assert main(["illuminance", office, "--grid=-2,-1,2,1,3,3", "--indirect-cache"]) == 2
    err = capsys.readouterr().err
    assert "(--indirect-cache): needs --indirect" in err and len(err.strip().splitlines()) == 1
