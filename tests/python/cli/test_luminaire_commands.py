"""`patina luminaire info|plot|ugr`: the summary (text and JSON) of the bundled files, the polar
plot written, the UGR table (text and JSON), and bad files ending with one line, exit status 2 and no traceback."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from conftest import ROOT
from patina.cli import main

LUM = os.path.join(ROOT, "materials", "luminaires")


def test_info_text_and_json(capsys):
    assert main(["luminaire", "info", os.path.join(LUM, "streetlight.ies")]) == 0
    text = capsys.readouterr().out
    assert "LM-63-2002" in text and "bilateral" in text and "declared 12000" in text and "C90-C270" in text
    assert main(["luminaire", "info", "--json", os.path.join(LUM, "downlight.ies")]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["format"] == "IES" and info["version"] == "LM-63-2019" and info["symmetry"] == "rotational"
    assert info["lumens_declared"] == 1500 and abs(info["light_output_ratio"] - 1) < 0.005
    # cos^3: half of the peak at acos(0.5^(1/3)) = 37.47 deg from nadir, both planes alike
    assert info["beam_angle_deg"]["C0-C180"] == pytest.approx(2 * 37.47, abs=0.3)
    assert info["beam_angle_deg"]["C90-C270"] == pytest.approx(info["beam_angle_deg"]["C0-C180"])
    assert info["max_at_deg"] == {"horizontal": 0.0, "vertical": 0.0}


def test_info_of_type_b_and_ldt(capsys):
    assert main(["luminaire", "info", "--json", os.path.join(LUM, "floodlight.ies")]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["type"] == "B" and set(info["beam_angle_deg"]) == {"horizontal", "vertical"}
    # Gaussian beam exp(-(H/22)^2): 50 % at H = 22 sqrt(ln 2) = 18.3 deg; the spill widens it a little
    assert 36 < info["beam_angle_deg"]["horizontal"] < 40
    assert main(["luminaire", "info", os.path.join(LUM, "streetlight.ldt")]) == 0
    assert "EULUMDAT" in capsys.readouterr().out


@pytest.mark.parametrize("name", ["streetlight.ldt", "floodlight.ies"])
def test_plot_writes_a_png(tmp_path, capsys, name):
    out = os.path.join(tmp_path, "polar.png")
    assert main(["luminaire", "plot", os.path.join(LUM, name), "--out", out]) == 0
    with open(out, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert os.listdir(tmp_path) == ["polar.png"]  # no temporary left behind


def test_bad_file_exits_2_with_one_line(tmp_path):
    bad = os.path.join(tmp_path, "bad.ies")
    with open(bad, "w") as f:
        f.write("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n100 50\n")
    # a separate process (the installed package), so the whole command path is exercised
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "luminaire", "info", bad], check=False, capture_output=True, text=True
    )
    assert r.returncode == 2 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in r.stderr
    assert bad in lines[0] and "line 7" in lines[0] and "declares 7 values but only 6" in lines[0]


def test_missing_file_exits_2(tmp_path, capsys):
    assert main(["luminaire", "plot", os.path.join(tmp_path, "none.ldt"), "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "none.ldt" in err[0]


def test_ugr_table_text_and_json(capsys):
    assert main(["luminaire", "ugr", os.path.join(LUM, "downlight.ies")]) == 0
    text = capsys.readouterr().out
    assert "crosswise" in text and "endwise" in text and "0.7/0.5/0.2" in text and "12H x 8H" in text
    assert main(["luminaire", "ugr", "--json", "--spacing", "0.25", os.path.join(LUM, "downlight.ies")]) == 0
    table = json.loads(capsys.readouterr().out)
    assert table["spacing_to_height"] == 0.25 and len(table["rows"]) == 190
    assert {r["view"] for r in table["rows"]} == {"crosswise", "endwise"}


def test_ugr_of_a_type_b_file_exits_2_with_one_line():
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "luminaire", "ugr", os.path.join(LUM, "floodlight.ies")],
        check=False,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "floodlight.ies (photometric type)" in r.stderr


@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "2.5"])
def test_ugr_spacing_out_of_range_exits_2_naming_the_option(capsys, value):
    assert main(["luminaire", "ugr", os.path.join(LUM, "downlight.ies"), f"--spacing={value}"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--spacing" in err


def test_ugr_refuses_abbreviated_options(capsys):
    assert main(["luminaire", "ugr", os.path.join(LUM, "downlight.ies"), "--spac", "0.25"]) == 2
    assert "--spac" in capsys.readouterr().err
