"""Tables as RGL tensor files (python/patina/export/rgl.py): resampled into the format's own
parameterisation, read back by Patina's RGL evaluator within stated bounds of the source
table, spectra upsampled or kept, anisotropy detected, and a table with a hole over the
incident angles refused before anything is written."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import patina
from patina.errors import FormatError
from patina.export.rgl import (
    HOLE_DEG,
    RglSource,
    check_incidence,
    check_pairs,
    is_isotropic,
    table_source,
    write_rgl_file,
)
from patina.synthetic.analytic import ggx_anisotropic
from patina.table.formats.rgl_brdf import read_rgl_brdf
from patina.table.formats.rgl_writer import RglLayout
from rgl_tables import MODEL, WAVELENGTHS, plastic_table, shallow_table, spectral_table

# the bounds docs/export.md states for a table written at the default layout
MEDIAN_BOUND, P95_BOUND = 0.01, 0.15


@pytest.fixture(scope="module")
def plastic():
    return plastic_table()


def test_rgb_file_read_back_within_the_stated_bounds(plastic, tmp_path):
    out = str(tmp_path / "plastic.bsdf")
    report = write_rgl_file(table_source(plastic, "plastic.ptab"), out, "rgb")
    err = report["read_back_error"]
    assert report["channels"] == ["rgb"] and report["isotropic"] and report["spectra_from"] is None
    assert err["relative_error_median"] < MEDIAN_BOUND and err["relative_error_p95"] < P95_BOUND
    # independently of the report: the written file against the analytic BRDF the table holds
    wi, wo = check_pairs(85.0)
    # (the file holds f cos(theta_o), the value the format's readers return; the evaluator gives f)
    f = read_rgl_brdf(out).eval(wi, wo)
    rel = np.abs(f - MODEL(wi, wo)) / np.maximum(MODEL(wi, wo), 1e-2)
    assert np.median(rel.max(axis=1)) < MEDIAN_BOUND
    assert patina.load_brdf(out).source_format == "rgl"


def test_spectra_upsampled_from_rgb_read_back_to_the_same_colour(plastic, tmp_path):
    pytest.importorskip("mitsuba")
    out = str(tmp_path / "plastic_spectral.bsdf")
    report = write_rgl_file(table_source(plastic, "plastic.ptab"), out)
    assert report["channels"] == ["spectra"] and "Jakob-Hanika" in report["spectra_from"]
    err = report["read_back_error"]
    assert err["relative_error_median"] < MEDIAN_BOUND and err["relative_error_p95"] < P95_BOUND
    assert read_rgl_brdf(out).channel_kind == "spectral"


def test_a_spectral_table_keeps_its_own_wavelengths(tmp_path):
    out = str(tmp_path / "spectral.bsdf")
    report = write_rgl_file(table_source(spectral_table(), "spectral.ptab"), out)
    assert report["spectra_from"] == "the table's own spectra"
    assert report["wavelengths_nm"] == [400.0, 700.0, WAVELENGTHS.size]
    assert report["read_back_error"]["relative_error_median"] < MEDIAN_BOUND
    assert np.allclose(read_rgl_brdf(out).wavelengths, WAVELENGTHS)


def test_a_hole_over_the_incident_angles_is_refused_and_nothing_written(tmp_path):
    out = tmp_path / "shallow.bsdf"
    with pytest.raises(FormatError) as e:
        write_rgl_file(table_source(shallow_table(), "shallow.ptab"), str(out), "rgb")
    assert e.value.where == "incident angles" and "77.3, 85 deg" in e.value.problem and "0 to 60 deg" in e.value.problem
    assert os.listdir(tmp_path) == []


def test_an_anisotropic_source_gets_an_anisotropic_file(tmp_path):
    aniso = ggx_anisotropic(diffuse=(0.2, 0.2, 0.2), specular=0.04, alpha_x=0.15, alpha_y=0.45)
    assert not is_isotropic(aniso) and is_isotropic(MODEL)
    out = str(tmp_path / "aniso.bsdf")
    report = write_rgl_file(RglSource("aniso", aniso), out, "rgb")
    assert not report["isotropic"] and report["incident_angles"] == 12 * 17
    err = report["read_back_error"]
    assert err["relative_error_median"] < 0.02 and err["relative_error_p95"] < 0.3
    brdf = read_rgl_brdf(out)
    assert not brdf.isotropic
    # the file holds the anisotropy: the lobe differs when the pair turns by 90 degrees
    wi, wo = np.array([[0.5, 0.0, 0.866]]), np.array([[-0.45, 0.2, 0.87]])
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert abs(brdf.eval(wi, wo)[0, 1] / brdf.eval(wi @ turn.T, wo @ turn.T)[0, 1] - 1) > 0.2


def test_a_function_source_is_written_everywhere(tmp_path):
    out = str(tmp_path / "model.bsdf")
    report = write_rgl_file(RglSource("model", MODEL), out, "rgb")
    assert report["theta_i_deg"][1] == pytest.approx(85.0, abs=1e-3)
    assert report["read_back_error"]["relative_error_median"] < MEDIAN_BOUND


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(0.0, 89.9), min_size=1, max_size=12))
def test_incidence_check_refuses_exactly_the_tables_with_a_hole(incidences):
    """Refused iff some incident angle the file holds (12 from 0 to 85 deg) has no measured
    incidence within 10 deg; the message names those angles."""
    layout = RglLayout()
    needed = np.linspace(0.0, layout.max_theta_i_deg, layout.theta_i)
    have = np.round(np.array(incidences), 3)
    holes = [t for t in needed if np.min(np.abs(have - t)) > HOLE_DEG]
    source = RglSource("t.ptab", MODEL, incidences_deg=np.array(incidences))
    if not holes:
        check_incidence(source, layout)
        return
    with pytest.raises(FormatError) as e:
        check_incidence(source, layout)
    assert e.value.where == "incident angles" and f"{holes[-1]:.3g} deg" in e.value.problem
