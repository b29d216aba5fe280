"""MERL import: a file written from an analytic BRDF comes back as that BRDF."""

from __future__ import annotations

import numpy as np
import pytest

import patina
from conftest import WIDTHS
from patina.synthetic.analytic import MERL_SCALE, write_merl
from reference import evaluate, hemisphere


def test_layout_scales_and_knots(merl_file, merl_raw_values):
    brdf = patina.load_brdf(merl_file)
    assert brdf.parametrization == "halfdiff" and brdf.channels == 3
    th, td, pd = brdf.axes
    np.testing.assert_allclose(np.degrees(th), np.arange(90) ** 2 / 90.0, rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(np.degrees(td), np.arange(90), atol=1e-5)
    np.testing.assert_allclose(np.degrees(pd), np.arange(181), atol=1e-4)
    values = brdf.values
    # value = raw * scale, channel-major raw layout, index phi_d + 180 (theta_d + 90 theta_h)
    np.testing.assert_allclose(values[10, 20, 30], merl_raw_values[:, 10, 20, 30] * MERL_SCALE, rtol=1e-6)
    np.testing.assert_array_equal(values[:, :, 180], values[:, :, 0])  # the seam knot repeats phi_d = 0


def test_missing_markers_are_masked_and_reported(merl_file):
    brdf = patina.load_brdf(merl_file)
    assert brdf.table.missing_count == 2
    assert brdf.valid[5, 40, 100] == 0 and brdf.valid[60, 10, 7] == 0
    assert np.all(brdf.values[5, 40, 100] == 0)
    assert "missing: 2" in brdf.info()["provenance"]
    assert brdf.info()["missing_points"] == 2


def test_import_reproduces_the_analytic_brdf(merl_file, merl_model):
    brdf = patina.load_brdf(merl_file)
    wi, wo = hemisphere(40000, 11), hemisphere(40000, 12)
    # stay off the horizon, where MERL's 1-degree bins and the zeroed below-horizon
    # entries dominate, and measure the interpolation against the model itself
    keep = (wi[:, 2] > 0.2) & (wo[:, 2] > 0.2)
    wi, wo = wi[keep], wo[keep]
    got = brdf.eval(wi, wo)
    want = merl_model(wi.astype(np.float64), wo.astype(np.float64))
    rel = np.abs(got - want) / want
    assert np.median(rel) < 2e-3, np.median(rel)
    assert np.percentile(rel, 99) < 3e-2, np.percentile(rel, 99)


def test_every_width_matches_the_double_reference(merl_file):
    brdf = patina.load_brdf(merl_file)
    wi, wo = hemisphere(30000, 13, below=0.02), hemisphere(30000, 14, below=0.02)
    ref = evaluate(brdf, wi, wo)
    results = [brdf.eval(wi, wo, width=w) for w in WIDTHS]
    for r in results[1:]:
        np.testing.assert_array_equal(r, results[0])
    rel = np.abs(results[0] - ref) / np.maximum(ref, 1e-3)
    assert rel.max() < 2e-3, rel.max()
    assert np.median(rel) < 1e-5


def test_truncated_and_misdimensioned_files(tmp_path, merl_raw_values):
    good = tmp_path / "good.binary"
    write_merl(str(good), merl_raw_values)
    data = good.read_bytes()
    cases = {
        "short.binary": (data[:5], "truncated"),
        "cut.binary": (data[:-8], "truncated"),
        "long.binary": (data + b"\0" * 8, "trailing"),
        "dims.binary": (np.array([90, 90, 90], "<i4").tobytes() + data[12:], "90 x 90 x 180"),
    }
    for name, (content, message) in cases.items():
        path = tmp_path / name
        path.write_bytes(content)
        with pytest.raises(patina.FormatError, match=message) as err:
            patina.load_brdf(path)
        assert str(path) in str(err.value)
