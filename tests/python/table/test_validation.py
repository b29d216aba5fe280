"""`patina validate`: a clean table passes; tables broken on purpose are flagged."""

from __future__ import annotations

import json
import os
import struct
import subprocess
import sys
import zlib

import numpy as np
import pytest

import patina
from patina.cli import main
from patina.synthetic.analytic import (
    anisotropic_grid,
    anisotropic_table,
    ggx_anisotropic,
    plastic,
    sample_isotropic,
    ward_anisotropic,
)
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData
from patina.table.validation import directional_albedo, format_report, validate
from repo_paths import ROOT

THETA = np.radians(np.linspace(0, 89, 24))
PHI = np.radians(np.linspace(0, 180, 37))


def table(values_fn=None, mask=None) -> patina.Brdf:
    data = sample_isotropic(plastic(), THETA, THETA, PHI, "test")
    if values_fn is not None:
        data.values = values_fn(data.values.copy())
    data.mask = mask
    return patina.Brdf(table_from_data(data), "synthetic", "test")


def problems(brdf: patina.Brdf) -> list[str]:
    return validate(brdf).problems


def test_clean_table_passes():
    report = validate(table())
    assert report.ok, report.problems
    assert report.checks["reciprocity"]["p95"] < 1e-5
    assert 0.05 < report.checks["albedo"]["max"] < 1.0


def test_albedo_of_a_lambert_table_is_its_reflectance():
    lambert = table(lambda v: np.full_like(v, 0.7 / np.pi))
    a = directional_albedo(lambert, np.radians([0.0, 30.0, 60.0]))
    np.testing.assert_allclose(a, 0.7, rtol=1e-3)


def test_negative_values_are_flagged():
    def negate(v):
        v[3, 4, 5, 1] = -0.2
        return v

    report = validate(table(negate))
    assert any("negative" in p for p in report.problems)
    assert report.checks["negative"]["worst"][0]["channel"] == 1


def test_non_reciprocal_table_is_flagged():
    # multiply by a factor that depends on theta_i but not theta_o
    def skew(v):
        return v * (1.0 + 2.0 * np.sin(THETA))[:, None, None, None]

    assert any("not reciprocal" in p for p in problems(table(skew)))


def test_energy_creating_table_is_flagged():
    assert any("albedo" in p for p in problems(table(lambda v: v * 4.0)))


def test_holes_are_reported():
    mask = np.ones((THETA.size, THETA.size, PHI.size), bool)
    mask[5:8, 6, 10:14] = False
    report = validate(table(mask=mask))
    assert report.checks["coverage"]["missing"] == 12
    assert report.checks["coverage"]["longest_missing_run"] == 4
    assert any("missing" in p for p in report.problems)


def test_spikes_are_flagged():
    def spike(v):
        v[10, 12, 20, :] *= 30.0
        return v

    report = validate(table(spike))
    assert report.checks["spikes"]["count"] == 3
    first = report.checks["spikes"]["first"][0]
    assert first["theta_i"] == pytest.approx(np.degrees(THETA[10]), abs=1e-3)


def _ptab_with_nan(path):
    # a valid .ptab (checksum and all) whose payload holds a NaN: the reader refuses it
    brdf = table()
    brdf.save(path)
    raw = bytearray(path.read_bytes())
    raw[-8:-4] = struct.pack("<f", float("nan"))
    raw[-4:] = struct.pack("<I", zlib.crc32(bytes(raw[:-4])))
    path.write_bytes(bytes(raw))


def test_cli_exit_codes_and_json(tmp_path, bundled_ptab, capsys):
    assert main(["validate", bundled_ptab]) == 0
    assert "result: clean" in capsys.readouterr().out
    broken = tmp_path / "broken.ptab"
    table(lambda v: v * 4.0).save(broken)
    assert main(["validate", str(broken), "--json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert doc["ok"] is False and doc["problems"]
    assert set(doc["checks"]) == {"finite", "negative", "axes", "coverage", "reciprocity", "albedo", "spikes"}
    nan = tmp_path / "nan.ptab"
    _ptab_with_nan(nan)
    # validate reports the NaN (exit 1) where the other commands refuse the file (exit 2)
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "validate", str(nan)], check=False, capture_output=True, text=True
    )
    assert r.returncode == 1 and "Traceback" not in r.stderr
    assert "1 value is NaN" in r.stdout and "nan at byte" in r.stdout
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "info", str(nan)], check=False, capture_output=True, text=True
    )
    assert r.returncode == 2
    assert str(nan) in r.stderr and "not finite" in r.stderr and "Traceback" not in r.stderr


# ---------------------------------------------------------------- issue 33: anisotropic tables

ANISO_THETA = np.radians(np.linspace(0, 80, 9))
ANISO_PHI = np.radians(np.arange(0, 360, 20.0))
ANALYTIC_ANISOTROPIC = {
    "ward": lambda tangent: ward_anisotropic((0.05, 0.05, 0.06), (0.5, 0.5, 0.5), 0.4, 0.15, tangent=tangent),
    "ward1992": lambda tangent: ward_anisotropic(
        (0.05, 0.05, 0.06), (0.5, 0.5, 0.5), 0.4, 0.15, normalisation="ward1992", tangent=tangent
    ),
    "ggx": lambda tangent: ggx_anisotropic((0.2, 0.1, 0.05), 0.9, 0.4, 0.15, tangent=tangent),
}


@pytest.mark.parametrize("tangent", ["x", "y"])
@pytest.mark.parametrize("lobe", sorted(ANALYTIC_ANISOTROPIC))
def test_analytic_anisotropic_tables_are_reciprocal_with_either_tangent(lobe, tangent):
    data = anisotropic_table(ANALYTIC_ANISOTROPIC[lobe](tangent), ANISO_THETA, ANISO_PHI)
    report = validate(patina.Brdf(table_from_data(data), "analytic", "test"))
    assert report.checks["reciprocity"]["p95"] < 1e-5, report.problems
    assert not any(p.startswith("not reciprocal") for p in report.problems)


def test_different_incident_and_outgoing_knots_are_not_reciprocal_between_them():
    """Why the first brushed-metal failed: a lobe narrower than the knot spacing, sampled on
    different incident and outgoing knots, is interpolated differently on each side."""
    f = ANALYTIC_ANISOTROPIC["ward1992"]("x")
    theta_o, phi_i = np.radians(np.linspace(0, 85, 9)), np.radians(np.arange(0, 360, 30.0))
    wi, wo = anisotropic_grid(ANISO_THETA, phi_i, theta_o, ANISO_PHI)
    values = f(wi, wo).reshape(9, phi_i.size, 9, ANISO_PHI.size, 3).astype(np.float32)
    data = TableData("anisotropic", [ANISO_THETA, phi_i, theta_o, ANISO_PHI], values, "rgb")
    report = validate(patina.Brdf(table_from_data(data), "analytic", "test"))
    assert any(p.startswith("not reciprocal") and "knots differ" in p for p in report.problems)
    assert report.checks["reciprocity"]["same_incident_and_outgoing_knots"] is False


def test_the_bundled_brushed_metal_validates_clean():
    report = validate(patina.load_brdf(os.path.join(ROOT, "materials", "samples", "brushed-metal.astm")))
    assert report.ok, report.problems


def test_albedo_rows_of_an_anisotropic_table_name_phi_i():
    data = anisotropic_table(ANALYTIC_ANISOTROPIC["ggx"]("x"), ANISO_THETA, ANISO_PHI)
    text = format_report(validate(patina.Brdf(table_from_data(data), "analytic", "test")))
    rows = [line.strip() for line in text.splitlines() if line.strip().startswith("theta_i")]
    assert rows and all("phi_i" in r for r in rows)
    assert len({r.split(":")[0] for r in rows}) == len(rows)  # no place named twice
