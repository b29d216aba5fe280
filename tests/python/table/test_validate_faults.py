"""Issue 10, defects 1, 2 and 12 (tables): MERL's below-horizon cells are unreachable, not
missing; a readable table with NaN, infinite or beyond-float32 values is reported by
validate (exit 1, values listed with their place, the other checks run), and refused by
the other commands with a message naming the file and the byte or line; a .ptab text
field that is not UTF-8 is named with its byte."""

from __future__ import annotations

import json
import struct
import zlib

import numpy as np
import pytest

import patina
from patina.cli import main
from patina.errors import FormatError
from patina.native import _core
from patina.synthetic.analytic import merl_axes, merl_raw, plastic, write_merl
from patina.table.angles import halfdiff_to_directions
from patina.table.formats import table_from_data
from patina.table.formats.lenient import read_reporting_bad_values
from patina.table.formats.tabledata import TableData
from patina.table.validation import validate

CHECKS = {"finite", "negative", "axes", "coverage", "reciprocity", "albedo", "spikes"}


@pytest.fixture(scope="module")
def merl_like() -> np.ndarray:
    """A MERL raw array as the database stores it: -1 wherever wi or wo is below the horizon."""
    raw = merl_raw(plastic(diffuse=(0.3, 0.5, 0.2), specular=0.05, roughness=0.3))
    wi, wo = halfdiff_to_directions(*np.meshgrid(*merl_axes(), indexing="ij"))
    below = ((wi[:, 2] <= 0) | (wo[:, 2] <= 0)).reshape(90, 90, 180)
    raw[:, below] = -1.0
    return raw


def merl_file(tmp_path, raw: np.ndarray, name: str = "m.binary") -> str:
    path = str(tmp_path / name)
    write_merl(path, raw)
    return path


def test_merl_below_horizon_cells_are_unreachable_not_missing(tmp_path, merl_like, capsys):
    path = merl_file(tmp_path, merl_like)
    assert main(["validate", path, "--json"]) == 0
    coverage = json.loads(capsys.readouterr().out)["checks"]["coverage"]
    assert coverage["missing"] == 0
    assert coverage["unreachable_missing"] == int((merl_like[0] < 0).sum()) + int((merl_like[0, :, :, 0] < 0).sum())
    assert 0.2 < coverage["unreachable"] / (90 * 90 * 181) < 0.3  # about a quarter of a MERL grid


def test_a_hole_inside_the_measurable_domain_is_still_a_problem(tmp_path, merl_like, capsys):
    raw = merl_like.copy()
    raw[:, 20, 20, 40] = -1.0  # theta_h 4.4 deg, theta_d 20 deg: well above the horizon
    assert main(["validate", merl_file(tmp_path, raw)]) == 1
    out = capsys.readouterr().out
    assert "1 of " in out and "measurable grid points are missing" in out


def test_merl_nan_and_inf_are_listed_by_validate_and_the_other_checks_run(tmp_path, merl_like, capsys):
    raw = merl_like.copy()
    raw[1, 10, 20, 30] = np.nan
    raw[0, 5, 5, 5] = np.inf
    path = merl_file(tmp_path, raw)
    assert main(["validate", path, "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert set(doc["checks"]) == CHECKS
    finite = doc["checks"]["finite"]
    assert finite["non_finite"] == 2
    assert {p["where"] for p in finite["first"]} == {
        f"byte {12 + 8 * (0 * 1458000 + 5 * 16200 + 5 * 180 + 5)}",
        f"byte {12 + 8 * (1 * 1458000 + 10 * 16200 + 20 * 180 + 30)}",
    }
    assert doc["checks"]["coverage"]["missing"] == 0  # the bad cells are reported once, as bad values
    assert len(doc["problems"]) == 1 and "NaN, infinite" in doc["problems"][0]
    assert main(["info", path]) == 2  # the other commands refuse the file


def test_merl_values_beyond_float32_are_a_format_error_with_the_byte(tmp_path, merl_like, capsys):
    raw = merl_like.copy()
    raw[2, 3, 4, 5] = 1e300
    path = merl_file(tmp_path, raw)
    with pytest.raises(FormatError) as e:
        _core.read_merl(path)
    assert e.value.where == f"byte {12 + 8 * (2 * 1458000 + 3 * 16200 + 4 * 180 + 5)}"
    assert "too large for float32" in e.value.problem
    assert main(["validate", path]) == 1
    assert "1e+300 at byte" in capsys.readouterr().out


def small_table(provenance: str = "ABCDEFGH") -> patina.Brdf:
    th = np.radians(np.linspace(0, 89, 10))
    ph = np.radians(np.linspace(0, 180, 7))
    values = np.full((10, 10, 7, 3), 0.1)
    return patina.Brdf(table_from_data(TableData("isotropic", [th, th, ph], values, "rgb", provenance=provenance)))


def rewrite(path, change) -> None:
    raw = bytearray(path.read_bytes())
    change(raw)
    raw[-4:] = struct.pack("<I", zlib.crc32(bytes(raw[:-4])))  # a valid checksum: only the content is wrong
    path.write_bytes(bytes(raw))


@pytest.mark.parametrize("field", ["provenance", "units"])
def test_a_ptab_text_field_that_is_not_utf8_is_named_with_its_byte(tmp_path, field, capsys):
    path = tmp_path / "t.ptab"
    small_table().save(path)
    marker = b"ABCDEFGH" if field == "provenance" else b"1/sr"
    at = path.read_bytes().index(marker) + 1

    def spoil(raw: bytearray) -> None:
        raw[at] = 0xFF

    rewrite(path, spoil)
    with pytest.raises(FormatError) as e:
        _core.read_ptab(str(path))
    assert e.value.where == f"byte {at}, {field}" and "not UTF-8" in e.value.problem
    for command in ("info", "validate", "convert"):
        args = [command, str(path)] + ([str(tmp_path / "o.ptab")] if command == "convert" else [])
        assert main(args) == 2
        assert field in capsys.readouterr().err


def test_ptab_nan_is_listed_with_its_byte_and_grid_place(tmp_path):
    path = tmp_path / "t.ptab"
    small_table().save(path)
    values_at = len(path.read_bytes()) - 4 - 4 * 10 * 10 * 7 * 3

    def spoil(raw: bytearray) -> None:
        raw[values_at + 4 * 37 : values_at + 4 * 38] = struct.pack("<f", float("inf"))

    rewrite(path, spoil)
    brdf, bad = read_reporting_bad_values(path)
    assert bad.count == 1
    assert bad.places[0]["where"] == f"byte {values_at + 4 * 37}" and bad.places[0]["channel"] == 1
    report = validate(brdf, bad=bad)
    assert set(report.checks) == CHECKS and len(report.problems) == 1


ASTM = """#ASTM E1392-96
SOURCE test
VARS theta_i phi_i theta_s phi_s R G B
"""


def astm_grid(bad_token: str) -> str:
    rows = []
    for ti in (0.0, 0.5):
        for to in (0.0, 0.4, 0.8):
            for ps in (0.0, 3.14159):
                rows.append([ti, 0.0, to, ps, 0.1, 0.2, 0.3])
    lines = [" ".join(f"{v:g}" for v in r) for r in rows]
    lines[4] = lines[4].rsplit(" ", 1)[0] + " " + bad_token
    return ASTM + "\n".join(lines) + "\n"


@pytest.mark.parametrize("token", ["nan", "NaN", "inf", "-Infinity", "1e999", "1e39"])
def test_astm_bad_values_are_listed_with_their_line(tmp_path, token, capsys):
    path = tmp_path / "t.astm"
    path.write_text(astm_grid(token))
    assert main(["info", str(path)]) == 2  # refused as before
    capsys.readouterr()
    assert main(["validate", str(path), "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    first = doc["checks"]["finite"]["first"][0]
    assert first["where"] == "line 8" and first["value"] == token and "(B)" in first["column"]
    assert doc["checks"]["coverage"]["missing"] == 0 and set(doc["checks"]) == CHECKS
