"""NVIDIA MDL .mbsdf files (python/patina/table/formats/mdl.py): written here from the
format's definition, read back exactly (float32) at the cell centres, transmission
skipped with a note or refused when alone, damaged files one FormatError (hypothesis)."""

from __future__ import annotations

import struct

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patina
from format_writers import mbsdf_bytes
from patina.errors import FormatError
from patina.synthetic.analytic import isotropic_grid, plastic
from patina.table.formats.mdl import MAGIC, mdl_axes
from reader_fuzz import load_damaged

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)


def _write(tmp_path, raw: bytes, name: str = "m.mbsdf") -> str:
    path = tmp_path / name
    path.write_bytes(raw)
    return str(path)


@pytest.mark.parametrize("rgb", [True, False])
def test_values_read_back_at_the_cell_centres(tmp_path, rgb):
    brdf = patina.load_brdf(_write(tmp_path, mbsdf_bytes(MODEL, rgb=rgb)))
    assert brdf.parametrization == "isotropic" and brdf.channel_kind == ("rgb" if rgb else "mono")
    th, to, pd = mdl_axes(9, 12)
    wi, wo = isotropic_grid(th, to, pd)
    want = MODEL(wi, wo) if rgb else MODEL(wi, wo)[:, 1:2]
    assert np.allclose(brdf.eval(wi, wo), want.astype(np.float32), rtol=2e-5, atol=1e-7)
    assert 'author="tests"' in brdf.info()["provenance"]


def test_transmission_skipped_or_refused(tmp_path):
    both = patina.load_brdf(_write(tmp_path, mbsdf_bytes(MODEL, parts=("REFLECTION", "TRANSMISSION"))))
    assert "transmission block skipped" in both.info()["provenance"]
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, mbsdf_bytes(MODEL, parts=("TRANSMISSION",)), "t.mbsdf"))
    assert "only transmission data" in e.value.problem and e.value.where.startswith("byte ")


@pytest.mark.parametrize(
    "raw, where, problem",
    [
        (b"NVIDIA ARC MBSDF V2\n", "byte 0", "expected the header"),
        (MAGIC + b'a="b"\n', "file", "no MBSDF_DATA"),
        (MAGIC + b"MBSDF_DATA=\n" + struct.pack("<III", 2, 4, 4), "byte 32", "data type 2"),
        (MAGIC + b"MBSDF_DATA=\n" + struct.pack("<III", 0, 100000, 4), "byte 36", "res_theta 100000"),
        (MAGIC + b"MBSDF_DATA=\n" + struct.pack("<III", 1, 90, 180) + b"\0" * 64, "byte 32", "needs 17496000 bytes"),
    ],
)
def test_bad_files_name_the_byte(tmp_path, raw, where, problem):
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, raw))
    assert e.value.where == where and problem in e.value.problem


def test_negative_value_beyond_the_noise_named(tmp_path):
    raw = bytearray(mbsdf_bytes(MODEL, rgb=False))
    raw[-4:] = struct.pack("<f", -1.0)
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, bytes(raw)))
    assert e.value.where == f"byte {len(raw) - 4}" and "negative beyond measurement noise" in e.value.problem


def test_noise_just_below_zero_is_set_to_zero_and_noted(tmp_path):
    # as in NVIDIA's measured car paints: values a little below zero where the signal is near it
    raw = bytearray(mbsdf_bytes(MODEL, rgb=False))
    raw[-8:] = struct.pack("<ff", -1e-4, -2e-4)
    brdf = patina.load_brdf(_write(tmp_path, bytes(raw)))
    assert brdf.values.min() == 0.0 and brdf.values.reshape(-1)[-1] == 0.0
    assert "2 values slightly below 0 set to 0 (measurement noise: down to -0.0002" in brdf.info()["provenance"]


SMALL = mbsdf_bytes(MODEL, res_theta=3, res_phi=4)
FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(at=st.integers(min_value=0, max_value=len(SMALL) - 1), value=st.integers(0, 255), cut=st.booleans())
def test_damaged_files_raise_one_format_error(at, value, cut):
    load_damaged(SMALL, at, value, cut, "f.mbsdf", patina.load_brdf)
