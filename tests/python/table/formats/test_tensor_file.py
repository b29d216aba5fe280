"""The RGL tensor_file container (python/patina/table/formats/tensor_file.py): written and
read back, every damaged header refused with one FormatError naming the file and the
byte or field, never a crash or a large allocation (hypothesis)."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import load_or_format_error
from patina.errors import FormatError
from patina.table.formats.tensor_file import parse_tensor_file, read_tensor_file, tensor_file_bytes, write_tensor_file

SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
ARRAYS = {
    "theta_i": np.linspace(0, 1.4, 5, dtype=np.float32),
    "grid": np.arange(24, dtype=np.float64).reshape(2, 3, 4),
    "flag": np.array([1], np.uint8),
    "counts": np.array([[1, -2], [3, 4]], np.int16),
}
SMALL = tensor_file_bytes(ARRAYS)


def test_round_trip_keeps_names_dtypes_shapes_and_values(tmp_path):
    path = tmp_path / "t.bsdf"
    write_tensor_file(path, ARRAYS)
    tf = read_tensor_file(path)
    assert list(tf.fields) == list(ARRAYS)
    for name, a in ARRAYS.items():
        b = tf.array(name)
        assert b.dtype == a.dtype and b.shape == a.shape and np.array_equal(a, b)
        assert tf.fields[name].offset % 8 == 0
    assert [p.name for p in tmp_path.iterdir()] == ["t.bsdf"]  # no temporary left


def _fails(raw: bytes, where: str, problem: str) -> None:
    with pytest.raises(FormatError) as e:
        parse_tensor_file("x.bsdf", raw)
    assert e.value.path == "x.bsdf" and where in e.value.where and problem in e.value.problem


def test_bad_headers_name_the_place():
    _fails(b"tensor_fil", "byte 0", "too short")
    _fails(b"tensor_filE\x00" + SMALL[12:], "byte 0", "magic")
    _fails(SMALL[:12] + b"\x02\x00" + SMALL[14:], "byte 12", "version 2.0")
    _fails(SMALL[:14] + struct.pack("<I", 0) + SMALL[18:], "byte 14", "empty")
    _fails(SMALL[:14] + struct.pack("<I", 10**6) + SMALL[18:], "byte 14", "more than")
    _fails(SMALL[:200], "", "")  # truncated: somewhere in the data of a field


def test_declared_shape_larger_than_the_file_is_refused_before_allocating():
    raw = bytearray(SMALL)
    # the first field's shape (rank 1) follows name length 2, "theta_i" (7), rank 2, dtype 1, offset 8
    at = 18 + 2 + 7 + 2 + 1 + 8
    raw[at : at + 8] = struct.pack("<Q", 2**60)
    _fails(bytes(raw), "field 'theta_i' at byte 18", "needs")


def test_unknown_dtype_named():
    raw = bytearray(SMALL)
    raw[18 + 2 + 7 + 2] = 12
    _fails(bytes(raw), "field 'theta_i'", "dtype code 12")


def _check(tf) -> None:
    for name in tf.fields:
        tf.array(name)


@SETTINGS
@given(cut=st.integers(min_value=0, max_value=len(SMALL) - 1))
def test_truncated_anywhere(cut):
    load_or_format_error(SMALL[:cut], "t.bsdf", read_tensor_file, _check)


@SETTINGS
@given(at=st.integers(min_value=0, max_value=len(SMALL) - 1), value=st.integers(0, 255))
def test_any_byte_changed(at, value):
    raw = bytearray(SMALL)
    raw[at] = value
    load_or_format_error(bytes(raw), "t.bsdf", read_tensor_file, _check)


@SETTINGS
@given(at=st.integers(min_value=12, max_value=120), word=st.integers(min_value=0, max_value=2**64 - 1))
def test_any_header_word(at, word):
    raw = bytearray(SMALL)
    raw[at : at + 8] = word.to_bytes(8, "little")
    load_or_format_error(bytes(raw), "t.bsdf", read_tensor_file, _check)
