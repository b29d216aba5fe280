"""Refitting to the targets' model: a GGX source is recovered, a Ward source is brought to GGX
with its error measured as `fit` measures it."""

from __future__ import annotations

import pytest

from export_helpers import GGX_FIT, WARD_FIT, write_json
from patina.export.refit import measure, needs_refit, refit
from patina.export.source import load_source


def test_refit_of_a_ggx_fit_recovers_it(tmp_path):
    source = load_source(write_json(tmp_path / "g.json", GGX_FIT))
    material = refit(source, "g")
    assert material.lobes[0].alpha == pytest.approx(GGX_FIT["parameters"]["alpha"], rel=0.02)
    assert material.diffuse == pytest.approx([GGX_FIT["parameters"][f"rho_{c}"] for c in "rgb"], rel=0.02)
    metrics = measure(source.evaluate, material)
    assert metrics["relative_error_median"] < 0.01 and metrics["ciede2000_mean"] < 0.2


def test_ward_is_refitted_and_its_error_reported(tmp_path):
    source = load_source(write_json(tmp_path / "w.json", WARD_FIT))
    assert "not Lambert + GGX" in needs_refit(source, 1, ("ggx",))
    material = refit(source, "w")
    assert material.lobes[0].distribution == "ggx" and material.notes
    metrics = measure(source.evaluate, material)
    assert set(metrics) >= {"relative_error_median", "relative_error_p95", "ciede2000_mean", "ciede2000_p95"}
    assert 0 < metrics["relative_error_median"] < 1  # a different lobe: close, not equal


def test_lobe_count_and_distribution_decide_the_refit(tmp_path):
    source = load_source(write_json(tmp_path / "g.json", GGX_FIT))
    assert needs_refit(source, 1, ("ggx",)) == ""
    assert "no ggx lobe" in needs_refit(source, None, ("beckmann",))
