"""r-tables (patina.lighting.rtable): the bundled synthetic table, holes and negative values
refused naming the line, interpolation, and damaged files fuzzed (FormatError, nothing else)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import load_or_format_error
from patina.errors import FormatError
from patina.lighting.rtable import read_rtable
from repo_paths import ROOT

BUNDLED = os.path.join(ROOT, "materials", "rtables", "synthetic-road.rtab")
with open(BUNDLED, "rb") as _f:
    BYTES = _f.read()
SETTINGS = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def write(tmp_path, text: str) -> str:
    path = tmp_path / "t.rtab"
    path.write_text(text)
    return str(path)


def test_the_bundled_table_is_the_cie_grid_and_what_the_script_makes():
    t = read_rtable(BUNDLED)
    assert t.r.shape == (29, 20) and t.tan_gamma[-1] == 12 and t.beta_deg[-1] == 180
    import sys

    sys.path.insert(0, os.path.join(ROOT, "tools"))
    from make_rtable import synthetic_r_e4

    np.testing.assert_allclose(t.r * 1e4, synthetic_r_e4(), rtol=1e-12)
    assert 0.06 < t.q0() < 0.09  # the dark-asphalt range of the CIE's R3 class


def test_interpolation_hits_the_knots_folds_beta_and_is_zero_beyond_the_table(tmp_path):
    t = read_rtable(write(tmp_path, "beta: 0 90 180\n0 100 100 100\n1 50 30 10\n"))
    np.testing.assert_allclose(t([0, 90, -90, 270, 45], [1, 1, 1, 1, 0.5]), [50e-4, 30e-4, 30e-4, 30e-4, 70e-4])
    assert t(0, 1.5) == 0


def test_q0_of_a_lambertian_surface_is_its_q(tmp_path):
    tans = np.linspace(0, 12, 801)
    rows = "\n".join(f"{x:g} " + " ".join([f"{700 * np.cos(np.arctan(x)) ** 3:.9g}"] * 3) for x in tans)
    t = read_rtable(write(tmp_path, "beta: 0 90 180\n" + rows + "\n"))
    assert t.q0() == pytest.approx(0.07, rel=1e-3)


@pytest.mark.parametrize(
    ("text", "where", "problem"),
    [
        ("beta: 0 90\n0 1 2\n0.5 1\n", "line 3", "no holes"),
        ("beta: 0 90\n0 1 2\n0.5 1 -\n", "line 3, value 3", "a hole"),
        ("beta: 0 90\n0 1 2\n0.5 1 -3\n", "line 3, beta 90", "negative"),
        ("0 1 2\n", "line 1", "before the 'beta:'"),
        ("name: x\n", "", "no 'beta:' line"),
        ("beta: 0 90 45\n0 1 2 3\n", "line 1", "ascending"),
        ("beta: 0 90\n0.5 1 2\n", "tan gamma", "tan gamma 0"),
        ("beta: 0 190\n0 1 2\n", "line 1", "[0, 180]"),
        ("colour: red\nbeta: 0\n0 1\n", "line 1", "unknown header"),
        ("beta: 0 90\n0 1 nan\n", "line 2, value 3", "not finite"),
    ],
)
def test_bad_tables_are_refused_naming_the_line(tmp_path, text, where, problem):
    path = write(tmp_path, text)
    with pytest.raises(FormatError) as e:
        read_rtable(path)
    assert e.value.path == path and where in e.value.where and problem in e.value.problem


def test_a_missing_file_points_to_the_users_own_tables(tmp_path):
    with pytest.raises(FormatError, match="R1-R4 / C1-C2"):
        read_rtable(tmp_path / "R3.rtab")


def _check(table) -> None:
    assert np.all(table.r >= 0) and np.all(np.isfinite(table(np.array([10.0]), np.array([0.3]))))


@SETTINGS
@given(cut=st.integers(min_value=0, max_value=len(BYTES) - 1))
def test_truncated_tables_load_or_raise_format_error(cut):
    load_or_format_error(BYTES[:cut], "t.rtab", read_rtable, _check)


@SETTINGS
@given(at=st.integers(min_value=0, max_value=len(BYTES) - 1), value=st.integers(min_value=0, max_value=255))
def test_corrupted_bytes_load_or_raise_format_error(at, value):
    data = bytearray(BYTES)
    data[at] = value if data[at] != value else value ^ 1
    load_or_format_error(bytes(data), "t.rtab", read_rtable, _check)
