"""`patina convert TABLE out.bsdf`: an RGL tensor file with its read-back error printed; a
table that cannot be resampled ends with one line, exit 2 and nothing written."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from patina.cli import main
from patina.table.formats.rgl_brdf import read_rgl_brdf
from rgl_tables import plastic_table, shallow_table


def test_convert_writes_an_rgl_file_and_prints_its_read_back_error(tmp_path, capsys):
    source = str(tmp_path / "plastic.ptab")
    plastic_table().save(source)
    out = str(tmp_path / "plastic.bsdf")
    assert main(["convert", source, out, "--channels", "rgb"]) == 0
    printed = capsys.readouterr().out
    assert "RGL tensor file, isotropic, 12 incident directions, rgb" in printed
    median = float(printed.split("relative error median ")[1].split(",")[0])
    assert 0 < median < 0.01
    assert read_rgl_brdf(out).channel_kind == "rgb"
    assert main(["convert", source, str(tmp_path / "again.ptab"), "--channels", "rgb"]) == 2
    assert "--channels is for an RGL .bsdf output" in capsys.readouterr().err


def test_a_hole_over_the_incident_angles_is_one_line_exit_2(tmp_path):
    source = str(tmp_path / "shallow.ptab")
    shallow_table().save(source)
    out = tmp_path / "shallow.bsdf"
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "convert", source, str(out), "--channels", "rgb"],
        check=False, capture_output=True, text=True,
    )  # fmt: skip
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and r.stdout == "" and len(lines) == 1, r.stderr
    assert source in lines[0] and "(incident angles)" in lines[0] and "0 to 60 deg" in lines[0]
    assert not out.exists() and sorted(os.listdir(tmp_path)) == ["shallow.ptab"]


def test_spectral_is_the_default(tmp_path, capsys):
    pytest.importorskip("mitsuba")
    source = str(tmp_path / "plastic.ptab")
    plastic_table().save(source)
    assert main(["convert", source, str(tmp_path / "p.bsdf")]) == 0
    assert "spectra from RGB, Jakob-Hanika" in capsys.readouterr().out
    assert read_rgl_brdf(str(tmp_path / "p.bsdf")).channel_kind == "spectral"
