"""Property tests: every reader, fed damaged files, raises FormatError and nothing else."""

from __future__ import annotations

import os
import tempfile

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patina
from conftest import load_or_format_error

SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


def _small_ptab_bytes() -> bytes:
    from patina.table.formats import table_from_data
    from patina.table.formats.tabledata import TableData

    axes = [np.linspace(0, 1.5, 3), np.linspace(0, 1.5, 4), np.linspace(0, np.pi, 5)]
    values = np.linspace(0.1, 2, 3 * 4 * 5 * 3, dtype=np.float32).reshape(3, 4, 5, 3)
    mask = np.ones((3, 4, 5), bool)
    mask[1, 1, 1] = False
    brdf = patina.Brdf(table_from_data(TableData("isotropic", axes, values, "rgb", mask=mask, provenance="fuzz")))
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "t.ptab")
        brdf.save(path)
        with open(path, "rb") as f:
            return f.read()


PTAB = _small_ptab_bytes()


def _check_brdf(brdf) -> None:
    # whatever loads must evaluate without trouble
    out = brdf.eval(np.array([[0.0, 0.6, 0.8]], np.float32), np.array([[0.3, 0.0, 0.95]], np.float32))
    assert out.shape == (1, brdf.channels)


def _load(content: bytes, suffix: str) -> None:
    load_or_format_error(content, "f" + suffix, patina.load_brdf, _check_brdf)


@SETTINGS
@given(cut=st.integers(min_value=0, max_value=len(PTAB) - 1))
def test_truncated_ptab(cut):
    _load(PTAB[:cut], ".ptab")


@SETTINGS
@given(at=st.integers(min_value=0, max_value=len(PTAB) - 1), value=st.integers(min_value=0, max_value=255))
def test_corrupted_ptab_byte(at, value):
    data = bytearray(PTAB)
    if data[at] == value:
        value ^= 1
    data[at] = value
    _load(bytes(data), ".ptab")


@SETTINGS
@given(at=st.integers(min_value=8, max_value=60), word=st.integers(min_value=0, max_value=2**32 - 1))
def test_ptab_header_fields_with_any_value(at, word):
    """Declared sizes anywhere in the header: checked against the bytes present, no huge allocation."""
    data = bytearray(PTAB)
    data[at : at + 4] = int(word).to_bytes(4, "little")
    _load(bytes(data), ".ptab")


@SETTINGS
@given(content=st.binary(max_size=2048))
def test_random_bytes_in_every_format(content):
    for suffix in (".ptab", ".binary", ".astm", ".csv", ".bsdf", ".mbsdf", ".bin"):
        _load(content, suffix)
    _load(PTAB[:8] + content, ".ptab")
    _load(b"tensor_file\x00\x01\x00" + content, ".dat")  # an RGL file, recognised by its magic
    _load(b"NVIDIA ARC MBSDF V1\nMBSDF_DATA=\n" + content, ".dat")  # an MDL file likewise


@SETTINGS
@given(dims=st.tuples(*[st.integers(min_value=-(2**31), max_value=2**31 - 1)] * 3), tail=st.binary(max_size=512))
def test_merl_with_any_dims(dims, tail):
    _load(np.array(dims, "<i4").tobytes() + tail, ".binary")
