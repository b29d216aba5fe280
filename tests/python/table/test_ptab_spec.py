"""docs/ptab.md, written independently here: files built from the spec read back exactly,
and spec-valid files with bad contents (non-monotonic axes, NaN, inf) are refused clearly."""

from __future__ import annotations

import itertools
import math
import struct
import zlib

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import patina

MAGIC = b"PTAB\r\n\x1a\n"
PARAMS = {"isotropic": (0, 3), "anisotropic": (1, 4), "halfdiff": (2, 3)}


def spec_bytes(param, lengths, knots, values, channels=3, kind=1, mask=None, symmetry=0, units="1/sr", prov="spec"):
    code, dims = PARAMS[param]
    out = bytearray(MAGIC)
    out += struct.pack("<7I", 1, code, kind, symmetry, 1 if mask is not None else 0, dims, channels)
    out += struct.pack(f"<{dims}I", *lengths)
    for text in (units, prov):
        raw = text.encode()
        out += struct.pack("<I", len(raw)) + raw
    for k in knots:
        out += np.asarray(k, "<f4").tobytes()
    if mask is not None:
        m = np.asarray(mask, np.uint8).tobytes()
        out += m + b"\0" * (-len(m) % 4)
    out += np.asarray(values, "<f4").tobytes()
    out += struct.pack("<I", zlib.crc32(bytes(out)))
    return bytes(out)


def test_spec_file_reads_back_exactly(tmp_path):
    knots = [np.linspace(0, 1.5, 4), np.array([0.0, 0.2, 1.0]), np.linspace(0, math.pi, 5)]
    values = np.arange(4 * 3 * 5 * 3, dtype=np.float32) / 7
    mask = np.ones(60, np.uint8)
    mask[17] = 0
    values.reshape(60, 3)[17] = 0
    path = tmp_path / "spec.ptab"
    path.write_bytes(spec_bytes("isotropic", [4, 3, 5], knots, values, mask=mask, symmetry=1, prov="written by hand"))
    brdf = patina.load_brdf(path)
    np.testing.assert_array_equal(brdf.values.reshape(-1), values)
    for a, b in zip(brdf.axes, knots):
        np.testing.assert_array_equal(a, b.astype(np.float32))
    assert brdf.valid.reshape(-1)[17] == 0 and brdf.table.missing_count == 1
    info = brdf.info()
    assert info["symmetry"] == ["reciprocity"] and info["provenance"] == "written by hand"
    # and Patina's writer produces the same bytes the spec describes
    out = tmp_path / "again.ptab"
    brdf.save(out)
    assert out.read_bytes() == path.read_bytes()


finite_or_not = st.one_of(
    st.floats(min_value=-1.0, max_value=4.0, width=32),
    st.sampled_from([math.nan, math.inf, -math.inf]),
)


@settings(max_examples=200, deadline=None)
@given(
    axis=st.lists(finite_or_not, min_size=2, max_size=6),
    value=finite_or_not,
    where=st.integers(min_value=0, max_value=10_000),
)
def test_bad_axes_and_values_are_refused(tmp_path_factory, axis, value, where):
    lengths = [len(axis), 2, 2]
    knots = [np.array(axis, np.float32), np.array([0.0, 1.0]), np.array([0.0, 3.0])]
    values = np.full(len(axis) * 4 * 3, 0.5, np.float32)
    values[where % values.size] = value
    path = tmp_path_factory.mktemp("spec") / "h.ptab"
    path.write_bytes(spec_bytes("isotropic", lengths, knots, values))
    monotonic = all(np.isfinite(axis)) and all(b > a for a, b in itertools.pairwise(axis))
    in_range = monotonic and -7 <= axis[0] and axis[-1] <= 7
    try:
        brdf = patina.load_brdf(path)
    except patina.FormatError as e:
        assert str(path) in str(e)
        assert not (in_range and math.isfinite(value)), f"refused a valid file: {e}"
        return
    assert in_range and math.isfinite(value), "accepted a bad file"
    assert np.all(np.isfinite(brdf.values))
