"""Tests for the ASTM E1392 BRDF text importer (python/patina/formats/astm.py).

Every test writes its own sample file into tmp_path.
"""

from __future__ import annotations

import math
import random
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patina.table.formats import astm

read_astm = astm.read_astm
FormatError = astm.FormatError
TableData = astm.TableData

THETAS = [0.0, 0.1, 0.3, 0.7, 1.2, 1.5]
PHI_DS = [0.0, 0.25, 1.0, 2.0, math.pi]


# ------------------------------------------------------------------ helpers


def analytic_rgb(theta_i: float, theta_o: float, phi_d: float) -> tuple[float, float, float]:
    """A simple smooth isotropic BRDF: Lambert + a Gaussian lobe around the mirror direction."""
    lobe = math.exp(-((theta_o - theta_i) ** 2 + (phi_d - math.pi) ** 2) / 0.3)
    return (0.2 / math.pi + lobe, 0.5 / math.pi + 0.5 * lobe, 0.1 / math.pi + 2.0 * lobe)


def astm_text(
    vars_line: str,
    rows: list[list[float]],
    *,
    header: list[str] | None = None,
    num_points: bool = True,
    sep: str = " ",
    newline: str = "\n",
) -> str:
    lines = ["#ASTM E1392-96"]
    lines += header if header is not None else ["SOURCE Patina tests", "DATE 2024-01-02"]
    if num_points:
        lines.append(f"NUM_POINTS {len(rows)}")
    lines.append(vars_line)
    lines += [sep.join(repr(float(v)) for v in row) for row in rows]
    return newline.join(lines) + newline


def write(tmp_path: Path, content: str | bytes, name: str = "sample.astm") -> Path:
    path = tmp_path / name
    path.write_bytes(content.encode("utf-8") if isinstance(content, str) else content)
    return path


def check_table(table: object) -> None:
    """Invariants every successfully read table must satisfy."""
    assert isinstance(table, TableData)
    assert table.parametrization in ("isotropic", "anisotropic")
    assert table.values.dtype == np.float32 and table.values.flags.c_contiguous
    shape = tuple(len(axis) for axis in table.axes)
    assert table.values.shape[:-1] == shape and table.values.shape[-1] >= 1
    for axis in table.axes:
        assert axis.dtype == np.float64 and len(axis) >= 2
        assert np.all(np.isfinite(axis)) and np.all(np.diff(axis) > 0)
    assert np.all(np.isfinite(table.values))
    assert table.units == "1/sr"


def base_lines() -> list[str]:
    """A valid 2x2x2 isotropic mono file; data rows are lines 5..12."""
    rows = [
        f"{ti} 0 {to} {pd} {0.1 + ti + 2 * to + 3 * pd}" for ti in (0.1, 0.5) for to in (0.2, 0.6) for pd in (0.0, 1.0)
    ]
    return ["#ASTM E1392-96", "SOURCE unit test", "NUM_POINTS 8", "VARS theta_i phi_i theta_s phi_s BRDF", *rows]


def joined(lines: list[str]) -> str:
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------- good files


def test_isotropic_rgb_irregular_grid_shuffled(tmp_path: Path) -> None:
    rows = [[ti, 0.0, to, pd, *analytic_rgb(ti, to, pd)] for ti in THETAS for to in THETAS for pd in PHI_DS]
    random.Random(7).shuffle(rows)
    path = write(tmp_path, astm_text("VARS theta_i phi_i theta_s phi_s R G B", rows))

    table = read_astm(path)

    check_table(table)
    assert table.parametrization == "isotropic"
    assert table.channel_kind == "rgb" and table.wavelengths is None
    assert [a.tolist() for a in table.axes] == [THETAS, THETAS, PHI_DS]
    expected = np.array(
        [[[analytic_rgb(ti, to, pd) for pd in PHI_DS] for to in THETAS] for ti in THETAS], dtype=np.float32
    )
    np.testing.assert_array_equal(table.values, expected)
    assert table.provenance == "ASTM E1392-96; SOURCE=Patina tests; DATE=2024-01-02; file=sample.astm"


def test_read_astm_accepts_str_and_pathlike(tmp_path: Path) -> None:
    path = write(tmp_path, joined(base_lines()))
    np.testing.assert_array_equal(read_astm(str(path)).values, read_astm(path).values)


def test_cornell_style_commas_and_negative_phi(tmp_path: Path) -> None:
    """Cornell exports: comma separated VARS and rows, phi_s in [-pi, 0], phi_i = 0."""
    rows = [[ti, 0.0, to, -pd, *analytic_rgb(ti, to, pd)] for ti in THETAS[:3] for to in THETAS for pd in PHI_DS]
    path = write(tmp_path, astm_text("VARS theta_i,phi_i,theta_s,phi_s,R,G,B", rows, sep=","))

    table = read_astm(path)

    check_table(table)
    assert table.parametrization == "isotropic"
    np.testing.assert_array_equal(table.axes[2], PHI_DS)
    assert table.values.shape == (3, 6, 5, 3)
    np.testing.assert_array_equal(table.values[1, 4, 3], np.float32(analytic_rgb(0.1, 1.2, 2.0)))


def test_constant_nonzero_phi_i_is_isotropic(tmp_path: Path) -> None:
    phi_i = 0.4
    rows = [
        [ti, phi_i, to, phi_i + pd, ti + to + pd] for ti in (0.2, 0.6) for to in (0.1, 0.9) for pd in (0.0, 0.5, 1.5)
    ]
    table = read_astm(write(tmp_path, astm_text("VARS theta_i phi_i theta_s phi_s BRDF", rows)))
    assert table.parametrization == "isotropic"
    np.testing.assert_allclose(table.axes[2], [0.0, 0.5, 1.5], atol=1e-12)
    np.testing.assert_allclose(table.values[1, 0, 2, 0], 0.6 + 0.1 + 1.5, rtol=1e-6)


def test_missing_phi_i_column_means_zero(tmp_path: Path) -> None:
    rows = [[ti, to, pd, ti * to + pd] for ti in (0.2, 0.6) for to in (0.1, 0.9) for pd in (0.0, 2.0)]
    table = read_astm(write(tmp_path, astm_text("VARS theta_i theta_s phi_s BRDF", rows)))
    assert table.parametrization == "isotropic" and table.values.shape == (2, 2, 2, 1)


def test_anisotropic(tmp_path: Path) -> None:
    theta_i, phi_i, theta_o, phi_o = [0.2, 0.9], [0.0, math.pi / 2, -math.pi / 2], [0.0, 0.5, 1.1], [0.0, 1.0, 2.5, 5.0]

    def f(ti: float, pi: float, to: float, po: float) -> float:
        return 0.1 + ti + 0.3 * math.cos(pi) + 0.2 * math.sin(pi) + to * po

    rows = [[a, b, c, d, f(a, b, c, d)] for a in theta_i for b in phi_i for c in theta_o for d in phi_o]
    random.Random(3).shuffle(rows)
    path = write(tmp_path, astm_text("VARS theta_i phi_i theta_o phi_o BRDF", rows))

    table = read_astm(path)

    check_table(table)
    assert table.parametrization == "anisotropic" and table.channel_kind == "mono"
    phi_i_sorted = sorted(np.mod(phi_i, 2 * math.pi))
    np.testing.assert_array_equal(table.axes[0], theta_i)
    np.testing.assert_array_equal(table.axes[1], phi_i_sorted)
    np.testing.assert_array_equal(table.axes[2], theta_o)
    np.testing.assert_array_equal(table.axes[3], phi_o)
    assert table.values.shape == (2, 3, 3, 4, 1)
    # phi_i = -pi/2 is the last phi_i axis value (3 pi / 2)
    assert table.values[1, 2, 2, 3, 0] == np.float32(f(0.9, -math.pi / 2, 1.1, 5.0))
    assert table.values[0, 1, 1, 2, 0] == np.float32(f(0.2, math.pi / 2, 0.5, 2.5))


def test_xyz_lowercase_keywords_reordered_columns(tmp_path: Path) -> None:
    rows = [[ti, 0.0, to, pd, 3.0, 2.0, 1.0 + ti] for ti in (0.0, 0.4) for to in (0.0, 0.4) for pd in (0.0, 3.0)]
    text = astm_text("vars Theta_I PHI_I theta_s phi_s Z Y X", rows, header=["source lab"])
    table = read_astm(write(tmp_path, text))
    assert table.channel_kind == "xyz"
    np.testing.assert_array_equal(table.values[1, 0, 0], np.float32([1.4, 2.0, 3.0]))
    assert "SOURCE=lab" in table.provenance


@pytest.mark.parametrize(
    "names",
    [
        ("700nm", "450nm", "550nm"),
        ("brdf_700", "brdf_450", "brdf_550"),
        ("700", "450", "550"),
        ("w700", "W450", "w550"),
    ],
)
def test_spectral_sorted_by_wavelength(tmp_path: Path, names: tuple[str, ...]) -> None:
    rows = [[ti, 0.0, to, -pd, 7.0 + ti, 4.5, 5.5] for ti in (0.1, 0.5) for to in (0.2, 0.6) for pd in (0.0, 1.0, 2.0)]
    vars_line = "VARS theta_i,phi_i,theta_s,phi_s," + ",".join(names)
    table = read_astm(write(tmp_path, astm_text(vars_line, rows, sep=", ")))
    check_table(table)
    assert table.channel_kind == "spectral"
    assert table.wavelengths is not None and table.wavelengths.dtype == np.float64
    np.testing.assert_array_equal(table.wavelengths, [450.0, 550.0, 700.0])
    np.testing.assert_array_equal(table.values[1, 0, 2], np.float32([4.5, 5.5, 7.5]))


def test_mono(tmp_path: Path) -> None:
    table = read_astm(write(tmp_path, joined(base_lines())))
    check_table(table)
    assert table.channel_kind == "mono" and table.wavelengths is None
    assert table.values.shape == (2, 2, 2, 1)
    assert table.values[1, 0, 1, 0] == np.float32(0.1 + 0.5 + 0.4 + 3.0)


def test_crlf_latin1_tabs_blank_lines_and_comments(tmp_path: Path) -> None:
    lines = base_lines()
    lines.insert(1, "# gemessen bei 20 \xb0C")
    lines.insert(2, "SAMPLE\tProbe M\xfcller")
    lines.insert(8, "")
    lines.insert(9, "# a comment between rows")
    lines[-1] = lines[-1].replace(" ", "\t")
    raw = ("\r\n".join(lines) + "\r\n\r\n").encode("latin-1")
    assert b"\xfc" in raw and b"\r\n" in raw

    table = read_astm(write(tmp_path, raw))

    check_table(table)
    assert "SAMPLE=Probe M\xfcller" in table.provenance
    np.testing.assert_array_equal(table.values, read_astm(write(tmp_path, joined(base_lines()), "plain.astm")).values)


def test_utf8_bom(tmp_path: Path) -> None:
    table = read_astm(write(tmp_path, b"\xef\xbb\xbf" + joined(base_lines()).encode()))
    assert table.provenance.startswith("ASTM E1392-96")


def test_values_within_tolerance_are_merged(tmp_path: Path) -> None:
    lines = base_lines()
    lines[5] = lines[5].replace("0.1 0 0.2 1.0", "0.1000004 0 0.2 1.0000003")
    table = read_astm(write(tmp_path, joined(lines)))
    np.testing.assert_array_equal(table.axes[0], [0.1, 0.5])


def test_negative_values_are_allowed(tmp_path: Path) -> None:
    lines = base_lines()
    lines[4] = "0.1 0 0.2 0.0 -0.25"
    assert read_astm(write(tmp_path, joined(lines))).values[0, 0, 0, 0] == np.float32(-0.25)


# ---------------------------------------------------------------- bad files


def replace_line(number: int, text: str) -> list[str]:
    lines = base_lines()
    lines[number - 1] = text
    return lines


def delete_line(number: int) -> list[str]:
    lines = base_lines()
    del lines[number - 1]
    return lines


def truncated() -> list[str]:
    return base_lines()[:-2]


def duplicated_row() -> list[str]:
    lines = base_lines()
    lines[11] = lines[4]
    return lines


def missing_point() -> list[str]:
    lines = base_lines()
    del lines[7]  # the row (0.1, 0.6, 1.0) on line 8
    lines[2] = "NUM_POINTS 7"
    return lines


BAD_FILES = {
    "truncated": (truncated(), "NUM_POINTS", ["line 3", "8 data rows", "has 6", "line 10", "truncated"]),
    "extra column": (replace_line(7, "0.1 0 0.6 0.0 1.0 2.0"), "line 7", ["expected 5 numbers", "found 6"]),
    "missing column": (replace_line(7, "0.1 0 0.6 0.0"), "line 7", ["expected 5 numbers", "found 4"]),
    "extra column, comma+blank": (
        replace_line(7, "0.1, 0, 0.6, 0.0, 1.0, 2.0"),
        "line 7",
        ["expected 5 numbers", "found 6"],
    ),
    "short row, tabs": (replace_line(11, "0.5\t0\t0.6\t\t0.0"), "line 11", ["found 4"]),
    "trailing comma": (replace_line(12, "0.5,0,0.6,1.0,1.0,"), "line 12", ["empty field", "column 6"]),
    "non-numeric": (replace_line(6, "0.1 0 abc 1.0 1.0"), "line 6", ["'abc'", "column 3 (theta_s)", "not a number"]),
    "python-only number": (replace_line(6, "0.1 0 0.2 1_0 1.0"), "line 6", ["'1_0'", "not a number"]),
    "empty field": (replace_line(6, "0.1,0,,1.0,1.0"), "line 6", ["empty field", "column 3"]),
    "nan": (replace_line(8, "0.1 0 0.6 1.0 nan"), "line 8", ["NaN", "column 5 (BRDF)"]),
    "inf": (replace_line(9, "0.5 0 0.2 0.0 -Infinity"), "line 9", ["infinite"]),
    "overflow": (replace_line(9, "0.5 0 0.2 0.0 1e999"), "line 9", ["overflows"]),
    "float32 overflow": (replace_line(10, "0.5 0 0.2 1.0 1e300"), "line 10", ["float32"]),
    "missing VARS": (delete_line(4), "line 4", ["VARS"]),
    "duplicate row": (
        duplicated_row(),
        "line 12",
        ["duplicate grid point", "already given on line 5", "not on a tensor grid"],
    ),
    "missing grid point": (
        missing_point(),
        "grid",
        [
            "missing grid point",
            "(theta_i=0.1, theta_o=0.6, phi_d=1)",
            "not on a tensor grid",
            "resampling scattered data is not supported",
        ],
    ),
    "theta out of range": (
        replace_line(9, "0.5 0 2.0 0.0 1.0"),
        "line 9",
        ["column 3 (theta_s) = 2", "outside [0, pi/2]"],
    ),
    "negative theta": (replace_line(5, "-0.1 0 0.2 0.0 1.0"), "line 5", ["theta_i", "outside"]),
    "degrees": (replace_line(11, "45 0 0.6 0.0 1.0"), "line 11", ["degrees"]),
    "phi out of range": (replace_line(12, "0.5 0 0.6 7.0 1.0"), "line 12", ["[-2 pi, 2 pi]"]),
    "header junk": (replace_line(2, "!!! not a header"), "line 2", ["KEYWORD value"]),
    "bad NUM_POINTS": (replace_line(3, "NUM_POINTS eight"), "line 3", ["non-negative integer"]),
    "huge NUM_POINTS": (replace_line(3, "NUM_POINTS 999999999999999"), "NUM_POINTS", ["999999999999999", "has 8"]),
    "absurd NUM_POINTS": (replace_line(3, "NUM_POINTS " + "9" * 5000), "line 3", ["implausibly large"]),
    "unknown channels": (
        replace_line(4, "VARS theta_i phi_i theta_s phi_s R G Q"),
        "line 4",
        ["cannot tell", "R, G, Q"],
    ),
    "no theta_i column": (replace_line(4, "VARS incidence phi_i theta_s phi_s BRDF"), "line 4", ["no theta_i column"]),
    "no value column": (replace_line(4, "VARS theta_i phi_i theta_s phi_s"), "line 4", ["no value column"]),
    "two outgoing thetas": (
        replace_line(4, "VARS theta_i theta_o theta_s phi_s BRDF"),
        "line 4",
        ["both give theta_s"],
    ),
    "no data": (base_lines()[:4], "line 4", ["no data rows"]),
}


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_input_raises_format_error_with_place(tmp_path: Path, case: str) -> None:
    lines, where, fragments = BAD_FILES[case]
    path = write(tmp_path, joined(lines))
    with pytest.raises(FormatError) as info:
        read_astm(path)
    error = info.value
    assert error.where == where
    assert error.path == str(path)
    message = str(error)
    assert message.startswith(f"{path} ({where}): ")
    for fragment in fragments:
        assert fragment in message, (fragment, message)


@pytest.mark.parametrize("content", [b"", b"   \r\n\r\n\t\n"])
def test_empty_file(tmp_path: Path, content: bytes) -> None:
    with pytest.raises(FormatError) as info:
        read_astm(write(tmp_path, content))
    assert info.value.where == "line 1" and "empty" in str(info.value)


def test_only_header_no_vars(tmp_path: Path) -> None:
    with pytest.raises(FormatError) as info:
        read_astm(write(tmp_path, "#ASTM E1392-96\nSOURCE x\nNUM_POINTS 3\n"))
    assert info.value.where == "VARS" and "missing VARS" in str(info.value)


def test_binary_garbage(tmp_path: Path) -> None:
    garbage = bytes(random.Random(5).getrandbits(8) for _ in range(4096))
    with pytest.raises(FormatError) as info:
        read_astm(write(tmp_path, garbage))
    assert info.value.where.startswith("line ")


def test_utf16_garbage_is_format_error(tmp_path: Path) -> None:
    with pytest.raises(FormatError):
        read_astm(write(tmp_path, b"\xff\xfe" + b"\x00\xd8" * 3))


def test_single_valued_axis(tmp_path: Path) -> None:
    rows = [[0.3, 0.0, to, pd, 1.0] for to in (0.1, 0.2) for pd in (0.0, 1.0)]
    with pytest.raises(FormatError) as info:
        read_astm(write(tmp_path, astm_text("VARS theta_i phi_i theta_s phi_s BRDF", rows)))
    assert info.value.where == "theta_i" and "at least 2" in str(info.value)


def test_scattered_data_is_rejected_without_building_the_grid(tmp_path: Path) -> None:
    rng = np.random.default_rng(11)
    n = 3000
    rows = np.column_stack(
        [
            rng.uniform(0, 1.5, n),
            np.zeros(n),
            rng.uniform(0, 1.5, n),
            rng.uniform(-math.pi, math.pi, n),
            rng.uniform(0, 1, n),
        ]
    )
    path = write(tmp_path, astm_text("VARS theta_i phi_i theta_s phi_s BRDF", rows.tolist()))
    with pytest.raises(FormatError) as info:  # 3000**3 grid points would not fit in memory
        read_astm(path)
    assert info.value.where == "grid" and "not on a tensor grid" in str(info.value)


def test_anisotropic_missing_point(tmp_path: Path) -> None:
    rows = [[a, b, c, d, 1.0] for a in (0.1, 0.2) for b in (0.0, 1.0) for c in (0.1, 0.2) for d in (0.0, 1.0)]
    del rows[-1]
    with pytest.raises(FormatError) as info:
        read_astm(write(tmp_path, astm_text("VARS theta_i phi_i theta_s phi_s BRDF", rows)))
    assert "(theta_i=0.2, phi_i=1, theta_o=0.2, phi_o=1)" in str(info.value)


def test_missing_file_is_os_error(tmp_path: Path) -> None:
    with pytest.raises(OSError):
        read_astm(tmp_path / "does-not-exist.astm")


# ------------------------------------------------------------- properties


def _valid_samples() -> list[bytes]:
    iso = [[ti, 0.0, to, pd, *analytic_rgb(ti, to, pd)] for ti in (0.0, 0.7) for to in (0.3, 1.2) for pd in (0.0, 3.0)]
    aniso = [
        [a, b, c, d, a + b + c + d] for a in (0.1, 0.2) for b in (0.0, 1.0) for c in (0.1, 0.2) for d in (0.0, 1.0)
    ]
    return [
        astm_text("VARS theta_i,phi_i,theta_s,phi_s,R,G,B", iso, sep=",", newline="\r\n").encode(),
        astm_text("VARS theta_i phi_i theta_o phi_o BRDF", aniso).encode(),
        astm_text("VARS theta_i phi_i theta_s phi_s 450nm 550nm 650nm", iso, header=["SAMPLE M\xfcller"]).encode(
            "latin-1"
        ),
        joined(base_lines()).encode(),
    ]


VALID_SAMPLES = _valid_samples()


def _read_or_format_error(path: Path) -> None:
    try:
        table = read_astm(path)
    except FormatError as error:
        assert error.where and error.problem
        return
    check_table(table)


def test_valid_samples_are_valid(tmp_path: Path) -> None:
    for index, sample in enumerate(VALID_SAMPLES):
        check_table(read_astm(write(tmp_path, sample, f"valid{index}.astm")))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(content=st.binary(max_size=2048))
def test_random_bytes_never_crash(tmp_path: Path, content: bytes) -> None:
    _read_or_format_error(write(tmp_path, content))


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(sample=st.sampled_from(VALID_SAMPLES), data=st.data())
def test_mutated_valid_files_never_crash(tmp_path: Path, sample: bytes, data: st.DataObject) -> None:
    kind = data.draw(st.sampled_from(["truncate", "flip", "delete line", "duplicate line", "insert"]))
    if kind == "truncate":
        mutated = sample[: data.draw(st.integers(0, len(sample)))]
    elif kind == "flip":
        at = data.draw(st.integers(0, len(sample) - 1))
        mutated = sample[:at] + bytes([sample[at] ^ data.draw(st.integers(1, 255))]) + sample[at + 1 :]
    elif kind == "insert":
        at = data.draw(st.integers(0, len(sample)))
        mutated = sample[:at] + data.draw(st.binary(min_size=1, max_size=8)) + sample[at:]
    else:
        lines = sample.split(b"\n")
        at = data.draw(st.integers(0, len(lines) - 1))
        if kind == "delete line":
            del lines[at]
        else:
            lines.insert(at, lines[at])
        mutated = b"\n".join(lines)
    _read_or_format_error(write(tmp_path, mutated))


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_complete_grid_in_any_order_round_trips(tmp_path: Path, data: st.DataObject) -> None:
    angle = st.floats(0.0, math.pi / 2, allow_nan=False)
    theta_i = sorted(data.draw(st.sets(angle, min_size=2, max_size=4)))
    theta_o = sorted(data.draw(st.sets(angle, min_size=2, max_size=4)))
    phi_d = sorted(data.draw(st.sets(st.floats(0.0, math.pi), min_size=2, max_size=4)))
    for axis in (theta_i, theta_o, phi_d):
        if np.any(np.diff(axis) <= 1e-6):
            return  # values closer than the merge tolerance are one grid value by design
    rows = [[a, 0.0, b, c, a + 2 * b + 3 * c] for a in theta_i for b in theta_o for c in phi_d]
    random.Random(data.draw(st.integers(0, 1000))).shuffle(rows)
    table = read_astm(write(tmp_path, astm_text("VARS theta_i phi_i theta_s phi_s BRDF", rows)))
    check_table(table)
    for got, want in zip(table.axes, (theta_i, theta_o, phi_d), strict=True):
        np.testing.assert_array_equal(got, want)
    expected = np.array([[[a + 2 * b + 3 * c for c in phi_d] for b in theta_o] for a in theta_i])
    np.testing.assert_array_equal(table.values[..., 0], expected.astype(np.float32))
