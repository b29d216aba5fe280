"""RGL .bsdf files as Patina tables (python/patina/table/formats/rgl.py): recognised by
content, resampled within a small error that the provenance reports, and accepted by the
table commands; a damaged file ends with one line and exit status 2."""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import patina
from patina.cli import main
from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.angles import angles_to_directions
from patina.table.formats.loading import detect_format
from patina.table.formats.rgl_writer import RglLayout, write_rgl

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)


@pytest.fixture(scope="module")
def bsdf(tmp_path_factory) -> str:
    path = str(tmp_path_factory.mktemp("rgl") / "plastic.bsdf")
    write_rgl(path, MODEL)
    return path


def test_table_matches_the_analytic_brdf_and_reports_its_resampling_error(bsdf):
    brdf = patina.load_brdf(bsdf)
    assert brdf.source_format == "rgl" and brdf.parametrization == "halfdiff" and brdf.channel_kind == "rgb"
    provenance = brdf.info()["provenance"]
    assert "RGL tensor_file 1.0 (isotropic, rgb, jacobian on)" in provenance
    p95 = float(provenance.split("95% ")[1].split(",")[0])
    assert 0 < p95 < 0.1  # the table against the file's own evaluation
    rng = np.random.default_rng(11)
    n = 3000
    wi = angles_to_directions(np.arccos(rng.uniform(0.34, 1, n)), rng.uniform(0, 2 * math.pi, n))
    wo = angles_to_directions(np.arccos(rng.uniform(0.26, 1, n)), rng.uniform(0, 2 * math.pi, n))
    want = MODEL(wi, wo)
    rel = (np.abs(brdf.eval(wi, wo) - want) / np.maximum(want, 1e-2)).max(axis=1)
    assert np.median(rel) < 0.01 and np.percentile(rel, 90) < 0.1


def test_detected_by_content_whatever_the_extension(bsdf, tmp_path):
    other = tmp_path / "plastic.dat"
    other.write_bytes(open(bsdf, "rb").read())
    assert detect_format(str(other)) == "rgl"
    empty = tmp_path / "empty.bsdf"
    empty.write_bytes(b"")
    with pytest.raises(FormatError, match="too short"):
        patina.load_brdf(empty)
    unknown = tmp_path / "thing.xyz"
    unknown.write_bytes(b"\x00\x01")
    with pytest.raises(FormatError) as e:
        patina.load_brdf(unknown)
    for name in (".ptab", "MERL", "ASTM", "CSV", "RGL .bsdf", "MDL .mbsdf", "UTIA .bin", "BSDF XML", "Zemax"):
        assert name in e.value.problem


def test_table_commands_accept_it(bsdf, tmp_path, capsys):
    assert main(["info", "--json", bsdf]) == 0
    assert json.loads(capsys.readouterr().out)["format"] == "rgl"
    out = str(tmp_path / "plastic.ptab")
    assert main(["convert", bsdf, out]) == 0
    assert "wrote" in capsys.readouterr().out
    converted = patina.load_brdf(out)
    assert "resampling error" in converted.info()["provenance"]
    assert main(["validate", "--json", bsdf]) in (0, 1)
    report = json.loads(capsys.readouterr().out)
    assert report is not None
    assert main(["eval", "--json", bsdf, "--wi", "30", "0", "--wo", "30", "180"]) == 0
    value = json.loads(capsys.readouterr().out)["values"]
    want = MODEL(
        angles_to_directions(math.radians(30), 0.0)[None], angles_to_directions(math.radians(30), math.pi)[None]
    )
    assert np.allclose(value, want[0], rtol=0.02)


def test_anisotropic_file_becomes_an_anisotropic_table(tmp_path):
    path = tmp_path / "aniso.bsdf"
    write_rgl(path, MODEL, layout=RglLayout(theta_i=5, phi_i=5, ndf=(8, 16), sigma=(8, 8), vndf=(8, 16), values=(8, 8)))
    brdf = patina.load_brdf(path)
    assert brdf.parametrization == "anisotropic" and "anisotropic, phi_i over 360/1 deg" in brdf.info()["provenance"]


def test_damaged_file_one_line_exit_2(bsdf, tmp_path):
    raw = bytearray(open(bsdf, "rb").read())
    bad = tmp_path / "bad.bsdf"
    bad.write_bytes(bytes(raw[:5000]))
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "info", str(bad)], check=False, capture_output=True, text=True
    )
    assert r.returncode == 2 and r.stdout == "" and "Traceback" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and str(bad) in lines[0] and "field '" in lines[0] and "needs" in lines[0]
    assert os.path.getsize(bad) == 5000
