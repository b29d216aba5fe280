"""Refitting to the targets' model: a GGX source is recovered, a Ward source is brought to GGX
with its error measured as `fit` measures it."""

from __future__ import annotations

import pytest

from export_helpers import GGX_FIT, WARD_FIT, write_json
from patina.export.refit import fit_reference, measure, needs_refit, refit, table_reference
from patina.export.source import load_source
from patina.table import load_brdf


def test_refit_of_a_ggx_fit_recovers_it(tmp_path):
    source = load_source(write_json(tmp_path / "g.json", GGX_FIT))
    material = refit(source, "g", fit_reference(source.evaluate))
    assert material.lobes[0].alpha == pytest.approx(GGX_FIT["parameters"]["alpha"], rel=0.02)
    assert material.diffuse == pytest.approx([GGX_FIT["parameters"][f"rho_{c}"] for c in "rgb"], rel=0.02)
    metrics = measure(fit_reference(source.evaluate), material)
    assert metrics["relative_error_median"] < 0.01 and metrics["ciede2000_mean"] < 0.2


def test_ward_is_refitted_and_its_error_reported(tmp_path):
    source = load_source(write_json(tmp_path / "w.json", WARD_FIT))
    assert "not Lambert + GGX" in needs_refit(source, 1, ("ggx",))
    material = refit(source, "w", fit_reference(source.evaluate))
    assert material.lobes[0].distribution == "ggx" and material.notes
    metrics = measure(fit_reference(source.evaluate), material)
    assert set(metrics) >= {"relative_error_median", "relative_error_p95", "ciede2000_mean", "ciede2000_p95"}
    assert 0 < metrics["relative_error_median"] < 1  # a different lobe: close, not equal


def test_lobe_count_and_distribution_decide_the_refit(tmp_path):
    source = load_source(write_json(tmp_path / "g.json", GGX_FIT))
    assert needs_refit(source, 1, ("ggx",)) == ""
    assert "no ggx lobe" in needs_refit(source, None, ("beckmann",))


def test_refit_against_the_measured_table(tmp_path, bundled_ptab):
    """Given the table, a Ward fit is refitted against the measurements themselves, and the
    error is the export's against them (as `fit` reports a fit's)."""
    source = load_source(write_json(tmp_path / "w.json", WARD_FIT))
    reference = table_reference(load_brdf(bundled_ptab))
    material = refit(source, "w", reference)
    against_table = measure(reference, material)
    assert against_table["ciede2000_mean"] < 2.0  # the red plastic table is a GGX-like plastic
    assert (
        against_table["ciede2000_mean"]
        < measure(reference, refit(source, "w2", fit_reference(source.evaluate)))["ciede2000_mean"]
    )
