"""UTIA .bin BRDFs (python/patina/table/formats/utia.py): written here from the database's
layout, read back exactly at the measured directions with phi wrapping at 360 degrees;
wrong sizes and bad values refused naming the byte; damaged files fuzzed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patina
from format_writers import utia_values
from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.formats.utia import FILE_BYTES, PHIS, THETAS
from reader_fuzz import load_damaged

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)


@pytest.fixture(scope="module")
def utia_file(tmp_path_factory) -> str:
    path = tmp_path_factory.mktemp("utia") / "m001_test.bin"
    path.write_bytes(utia_values(MODEL).astype("<f8").tobytes())
    return str(path)


def test_read_back_at_the_measured_directions_and_wrapping(utia_file):
    brdf = patina.load_brdf(utia_file)
    assert brdf.parametrization == "anisotropic" and brdf.source_format == "utia"
    values = utia_values(MODEL)
    rng = np.random.default_rng(3)
    for _ in range(20):
        ti, pi, to, po = rng.integers(0, THETAS), rng.integers(0, PHIS), rng.integers(0, THETAS), rng.integers(0, PHIS)
        got = brdf.eval_angles(*np.radians([ti * 15.0, pi * 7.5, to * 15.0, po * 7.5]))
        assert np.allclose(got, values[:, ti, pi, to, po], rtol=1e-6, atol=1e-7)
    # between 352.5 and 360 degrees the value interpolates towards phi = 0
    mid = brdf.eval_angles(math.radians(30), math.radians(356.25), math.radians(45), math.radians(90))
    ends = values[:, 2, [47, 0], 3, 12].mean(axis=1)
    assert np.allclose(mid, ends, rtol=1e-5)


def test_wrong_size_and_bad_values(tmp_path):
    short = tmp_path / "s.bin"
    short.write_bytes(b"\0" * 100)
    with pytest.raises(FormatError, match=f"100 bytes: a UTIA .bin BRDF .* has exactly {FILE_BYTES}"):
        patina.load_brdf(short)
    raw = bytearray(utia_values(MODEL).astype("<f8").tobytes())
    raw[8 * 1000 : 8 * 1001] = np.array([np.nan]).tobytes()
    bad = tmp_path / "n.bin"
    bad.write_bytes(bytes(raw))
    with pytest.raises(FormatError) as e:
        patina.load_brdf(bad)
    assert e.value.where == "byte 8000" and "not finite" in e.value.problem and "theta_i" in e.value.problem


FUZZ = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
CLEAN = utia_values(MODEL).astype("<f8").tobytes()


@FUZZ
@given(at=st.integers(min_value=0, max_value=FILE_BYTES - 1), value=st.integers(0, 255), cut=st.booleans())
def test_damaged_files_raise_one_format_error(at, value, cut):
    load_damaged(CLEAN, at, value, cut, "f.bin", patina.load_brdf)
