"""Zemax / LightTools tabular BSDF text (python/patina/table/formats/zemax.py): files
written here from the format's definition (directions about the specular direction),
read back within the resampling error; BTDF and damaged files refused with one line."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patina
from format_writers import zemax_text
from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.angles import angles_to_directions
from patina.table.formats.loading import detect_format
from patina.table.formats.zemax import scatter_directions
from reader_fuzz import load_damaged

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.4)


def _write(tmp_path, text: str, name: str = "vinyl.bsdf") -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_scatter_directions_follow_the_specular_convention():
    ti = np.radians(30.0)
    spec = scatter_directions(np.array(ti), np.array(0.0), np.array(0.0), np.array(0.0))
    assert np.allclose(spec, [-0.5, 0.0, math.cos(ti)])
    # azimuth 0 turns the specular direction towards the normal: by theta_i it reaches it
    assert np.allclose(scatter_directions(np.array(ti), np.array(0.0), np.array(0.0), np.array(ti)), [0, 0, 1])


@pytest.mark.parametrize("channels", [("Monochrome",), ("TristimulusX", "TristimulusY", "TristimulusZ")])
def test_read_back_within_the_resampling_error(tmp_path, channels):
    path = _write(tmp_path, zemax_text(MODEL, channels))
    assert detect_format(path) == "zemax"
    brdf = patina.load_brdf(path)
    assert brdf.parametrization == "isotropic" and brdf.channel_kind == ("mono" if len(channels) == 1 else "xyz")
    assert "Zemax tabular BSDF (planesymmetrical" in brdf.info()["provenance"]
    rng = np.random.default_rng(2)
    n = 2000
    wi = angles_to_directions(np.radians(rng.uniform(0, 60, n)), rng.uniform(0, 2 * math.pi, n))
    wo = angles_to_directions(np.radians(rng.uniform(0, 70, n)), rng.uniform(0, 2 * math.pi, n))
    want = MODEL(wi, wo)[:, : len(channels)]
    rel = (np.abs(brdf.eval(wi, wo) - want) / np.maximum(want, 0.05)).max(axis=1)
    assert np.median(rel) < 0.05 and np.percentile(rel, 90) < 0.25


def test_btdf_and_missing_data_refused(tmp_path):
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, zemax_text(MODEL, scatter_type="BTDF")))
    assert e.value.where == "ScatterType" and "Patina tables are reflection" in e.value.problem
    with pytest.raises(FormatError, match="no data block"):
        patina.load_brdf(_write(tmp_path, zemax_text(MODEL, data=False)))
    broken = zemax_text(MODEL).replace("DataBegin", "Data Begin")
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, broken))
    assert e.value.where.startswith("line ") and "expected DataBegin" in e.value.problem


SMALL = zemax_text(MODEL, aoi=[0, 40], azimuth=[0, 90, 180], radial=[0, 30, 60]).encode()
FUZZ = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(at=st.integers(min_value=0, max_value=len(SMALL) - 1), value=st.integers(0, 255), cut=st.booleans())
def test_damaged_files_raise_one_format_error(at, value, cut):
    load_damaged(SMALL, at, value, cut, "f.bsdf", patina.load_brdf)


def _with_last_value(value: str) -> str:
    """SMALL with its last value (line 24's third: the second TIS line is line 21) replaced."""
    return SMALL.decode().replace("2.027127e-01  0.000000e+00", f"2.027127e-01  {value}")


def test_noise_just_below_zero_is_set_to_zero_and_noted(tmp_path):
    brdf = patina.load_brdf(_write(tmp_path, _with_last_value("-1.0e-04")))
    assert (
        "Monochrome: 1 values slightly below 0 set to 0 (measurement noise: down to -0.0001"
        in (brdf.info()["provenance"])
    )
    assert float(np.min(brdf.values)) >= 0


def test_negative_value_beyond_the_noise_named(tmp_path):
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, _with_last_value("-0.05")))
    assert e.value.where == "line 21" and e.value.problem.startswith("Monochrome value 9 after this TIS line: -0.05")
    assert "negative beyond measurement noise" in e.value.problem
