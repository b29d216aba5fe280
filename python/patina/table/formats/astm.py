"""Reader for ASTM E1392 (-96 / -97) BRDF text files.

Accepted subset (see docs/astm.md for the long form):

* An optional magic comment ``#ASTM E1392-96`` (any ``#ASTM ...`` comment).
* Header lines ``KEYWORD value`` before the ``VARS`` line (``SOURCE``,
  ``DATE``, ``SAMPLE``, ``FORMAT``, ``WAVELENGTH``, ``POLARIZATION``, ...).
  Keywords are case-insensitive; the keyword may be followed by blanks, ``,``,
  ``=`` or ``:``.  ``NUM_POINTS N`` is checked against the rows present.
* ``VARS`` names the columns, separated by commas or blanks.  Angle columns
  (radians): ``theta_i``, ``phi_i`` (optional, 0 when absent), and the
  outgoing ``theta_s`` / ``phi_s`` (aliases ``_o``, ``_r``, ``_v``, ``_out``).
  Every other column is a channel: ``R G B`` -> "rgb", ``X Y Z`` -> "xyz",
  a single column (``BRDF``, ``value``, ...) -> "mono", two or more
  wavelength-named columns (``450``, ``450nm``, ``brdf_450``, ``w450``) ->
  "spectral", sorted by wavelength.
* After ``VARS``: one row per line, numbers separated by commas or blanks.
  Blank lines and ``#`` comments are skipped everywhere.
* Bytes are decoded as UTF-8 (a BOM is dropped), UTF-16 when it has a BOM,
  else Latin-1; CRLF, CR and LF line ends are all accepted.

The rows must form a complete tensor grid (in any row order).  When each
incidence angle theta_i comes with a single phi_i (normally phi_i == 0) the
table is "isotropic" with axes (theta_i, theta_o, phi_d), phi_d = |phi_s -
phi_i| folded into [0, pi]; otherwise it is "anisotropic" with axes
(theta_i, phi_i, theta_o, phi_o), phi folded into [0, 2 pi).  Axis values
closer than 1e-6 rad are merged.

Every problem in the file raises FormatError with ``where`` = "line N" (1-based)
or a field name ("VARS", "NUM_POINTS", an axis name, "grid", "file").  Only an
unreadable path (OSError) escapes as something else.
"""

from __future__ import annotations

import codecs
import math
import os
import re
from dataclasses import dataclass, field
from typing import NoReturn

import numpy as np

from patina.errors import FormatError
from patina.table.formats.resample import CannotResample, resample
from patina.table.formats.tabledata import BadValues, TableData

__all__ = ["read_astm"]

ANGLE_TOL = 1e-6  # rad: axis values closer than this are one grid value
PHI_ZERO_TOL = 1e-9  # rad: |phi_i| below this counts as exactly 0
TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi
NOT_A_GRID = "data not on a tensor grid (resampling scattered data is not supported yet)"

_WS = " \t\f\v"
_NUMBER = r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?"
_SEP = r"[ \t\f\v]*,[ \t\f\v]*|[ \t\f\v]+"
_NUMBER_RE = re.compile(_NUMBER)
_SEP_RE = re.compile(_SEP)
_ROW_RE = re.compile(rf"{_NUMBER}(?:(?:{_SEP}){_NUMBER})*")
_DATA_CHARS_RE = re.compile(r"[0-9eE+.,\- \t\f\v\n]*")
_DOUBLE_COMMA_RE = re.compile(r",[ \t\f\v]*,")
_KEY_RE = re.compile(r"([A-Za-z_][A-Za-z0-9_.\-]*)(?:(?:[ \t\f\v]*[,=:]|[ \t\f\v])(.*))?")
_WAVELENGTH_RE = re.compile(r"(?:brdf_?|wl_?|w|lambda_?)?([0-9]+(?:\.[0-9]+)?)[ \t]*(?:_?nm)?", re.IGNORECASE)
_NUM_POINTS_RE = re.compile(r"[0-9]{1,15}")
_NONFINITE_RE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)
_FLOAT32_MAX = float(np.finfo(np.float32).max)

# Canonical angle column -> accepted names (lower case).
_ANGLE_NAMES: dict[str, tuple[str, ...]] = {
    "theta_i": ("theta_i", "thetai", "theta_in"),
    "phi_i": ("phi_i", "phii", "phi_in"),
    "theta_s": ("theta_s", "theta_o", "theta_r", "theta_v", "theta_out", "thetas", "thetao"),
    "phi_s": ("phi_s", "phi_o", "phi_r", "phi_v", "phi_out", "phis", "phio"),
}
_ANGLE_ALIAS = {alias: canon for canon, names in _ANGLE_NAMES.items() for alias in names}
_TRISTIMULUS: tuple[tuple[str, tuple[str, str, str]], ...] = (
    ("rgb", ("r", "g", "b")),
    ("rgb", ("red", "green", "blue")),
    ("xyz", ("x", "y", "z")),
)
_PROVENANCE_VALUE_MAX = 100
# What a file can ask for (docs/astm.md, "Limits"): checked before the rows are converted,
# so that a small file cannot make the reader (or the resampler) allocate gigabytes.
MAX_FILE_BYTES = 512 << 20  # text: a few bytes a number, so up to ~100 M numbers
MAX_CHANNELS = 4096  # value columns: the .ptab limit


@dataclass
class _Header:
    """What the lines before the data say."""

    magic: str | None = None
    keywords: list[tuple[str, str]] = field(default_factory=list)
    num_points: int | None = None
    num_points_line: int = 0
    columns: list[str] = field(default_factory=list)
    vars_line: int = 0  # 1-based line of VARS
    data_start: int = 0  # 0-based index of the first line after VARS


@dataclass
class _Columns:
    """Which VARS column is which angle / channel."""

    angles: dict[str, int]  # canonical angle name -> column index ("phi_i" may be absent)
    channels: list[int]  # channel column indices, in output order
    channel_kind: str
    wavelengths: np.ndarray | None


@dataclass
class _Axis:
    """One grid axis: merged values and, per row, the index into them."""

    name: str
    values: np.ndarray
    labels: np.ndarray


# --------------------------------------------------------------------------- API


def read_astm(path: str | os.PathLike[str], resample: bool = False, report_bad: bool = False) -> TableData:
    """Read an ASTM E1392 BRDF text file into a TableData (see module docstring).

    resample: rows that are not a tensor grid are resampled onto one (formats/resample.py)
    instead of refused; the resampling error is reported in the provenance.
    report_bad: value columns holding NaN, infinity or numbers beyond float32 are listed in
    TableData.bad and their grid points masked (left out of a resampling) instead of refused
    (patina validate); bad angles are still refused."""
    name = os.fspath(path)
    if isinstance(name, bytes):
        name = os.fsdecode(name)
    with open(name, "rb") as handle:
        size = os.fstat(handle.fileno()).st_size
        if size > MAX_FILE_BYTES:
            _fail(name, "file", f"{size} bytes: larger than the {MAX_FILE_BYTES >> 20} MiB an ASTM file may have")
        raw = handle.read()
    try:
        return parse_astm_bytes(name, raw, resample, report_bad)
    except MemoryError:
        raise FormatError(name, "file", "not enough memory to read this file") from None


# ------------------------------------------------------------------- pipeline


def parse_astm_bytes(path: str, raw: bytes, resample: bool = False, report_bad: bool = False) -> TableData:
    lines = _split_lines(_decode(raw))
    header = _parse_header(path, lines)
    columns = _classify_columns(path, header)
    rows = _data_rows(lines, header.data_start)
    _check_row_count(path, header, rows)
    table = _parse_rows(path, header, rows, report_bad)
    line_numbers = np.fromiter((n for n, _ in rows), dtype=np.int64, count=len(rows))
    bad = BadValues() if report_bad else None
    bad_rows = np.zeros(len(rows), dtype=bool)
    if bad is not None:
        bad_rows = _collect_bad_values(header.columns, table, columns.channels, line_numbers, rows, bad)
    _check_finite(path, header.columns, table, line_numbers, rows)
    _check_channels_fit_float32(path, header.columns, table, columns.channels, line_numbers)
    _check_angle_ranges(path, header.columns, table, columns.angles, line_numbers)

    parametrization, axes = _grid_axes(table, columns.angles)
    try:
        flat = _grid_positions(path, axes, line_numbers)
    except FormatError:
        if not resample:
            raise
        data = _resampled(path, header, columns, parametrization, axes, table, ~bad_rows)
        data.bad = bad
        return data
    shape = tuple(len(axis.values) for axis in axes)
    values = np.empty((len(table), len(columns.channels)), dtype=np.float32)
    values[flat] = table[:, columns.channels]
    mask = None
    if bad is not None:
        points = np.zeros(len(table), dtype=bool)
        points[flat[bad_rows]] = True
        bad.points = points.reshape(shape)
        mask = ~bad.points if bad_rows.any() else None
    return TableData(
        parametrization=parametrization,
        axes=[axis.values for axis in axes],
        values=np.ascontiguousarray(values.reshape(*shape, len(columns.channels))),
        channel_kind=columns.channel_kind,
        wavelengths=columns.wavelengths,
        units="1/sr",
        provenance=_provenance(path, header),
        mask=mask,
        bad=bad,
    )


def _resampled(
    path: str,
    header: _Header,
    columns: _Columns,
    parametrization: str,
    axes: list[_Axis],
    table: np.ndarray,
    keep: np.ndarray,
) -> TableData:
    """keep: the rows to resample (those without bad values)."""
    coords = np.stack([axis.values[axis.labels] for axis in axes], axis=1)[keep]
    try:
        grid_axes, grid, error = resample(coords, table[keep][:, columns.channels], [a.name for a in axes])
    except CannotResample as e:
        _fail(path, "grid", f"data not on a tensor grid, and {e}")
    return TableData(
        parametrization=parametrization,
        axes=grid_axes,
        values=np.ascontiguousarray(grid, dtype=np.float32),
        channel_kind=columns.channel_kind,
        wavelengths=columns.wavelengths,
        units="1/sr",
        provenance=f"{_provenance(path, header)}; {error.describe()}",
    )


# -------------------------------------------------------------------- text


def _decode(raw: bytes) -> str:
    """UTF-16 with a BOM, else UTF-8 (BOM dropped), else Latin-1 (never fails)."""
    if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        try:
            return raw.decode("utf-16")
        except UnicodeDecodeError:
            pass
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def _split_lines(text: str) -> list[str]:
    """Split on LF, CRLF or CR only (not on the other Unicode line breaks)."""
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")


def _show(text: str, limit: int = 40) -> str:
    """A short, printable quotation of some file text for error messages."""
    return repr(text[:limit]) + ("..." if len(text) > limit else "")


def _fail(path: str, where: str, problem: str) -> NoReturn:
    raise FormatError(path, where, problem)


# ------------------------------------------------------------------ header


def _parse_header(path: str, lines: list[str]) -> _Header:
    """Read comment and KEYWORD lines up to and including VARS."""
    header = _Header()
    seen_anything = False
    for index, raw_line in enumerate(lines):
        lineno = index + 1
        line = raw_line.strip(_WS)
        if not line:
            continue
        seen_anything = True
        if line.startswith("#"):
            comment = line[1:].strip(_WS)
            if header.magic is None and comment.upper().startswith("ASTM"):
                header.magic = comment
            continue
        match = _KEY_RE.fullmatch(line)
        if match is None:
            if _ROW_RE.fullmatch(line):
                _fail(path, f"line {lineno}", "data row before any VARS line (missing VARS line naming the columns)")
            _fail(
                path,
                f"line {lineno}",
                f"expected a header line 'KEYWORD value' or 'VARS column names' before the data, got {_show(line)}",
            )
        key = match.group(1).upper()
        value = (match.group(2) or "").strip(_WS)
        if key == "VARS":
            header.columns = _split_names(path, lineno, value)
            header.vars_line = lineno
            header.data_start = index + 1
            return header
        if key == "NUM_POINTS":
            _set_num_points(path, header, lineno, value)
        else:
            header.keywords.append((key, value))
    if not seen_anything:
        _fail(path, "line 1", "file is empty (expected an ASTM E1392 header, a VARS line and data rows)")
    _fail(path, "VARS", f"missing VARS line naming the columns (file ends at line {len(lines)})")


def _set_num_points(path: str, header: _Header, lineno: int, value: str) -> None:
    if header.num_points is not None:
        _fail(path, f"line {lineno}", f"second NUM_POINTS (first on line {header.num_points_line})")
    if re.fullmatch(r"[0-9]+", value) is None:
        _fail(path, f"line {lineno}", f"NUM_POINTS must be a non-negative integer, got {_show(value)}")
    if _NUM_POINTS_RE.fullmatch(value) is None:
        _fail(path, f"line {lineno}", f"NUM_POINTS {_show(value)} is implausibly large")
    header.num_points = int(value)
    header.num_points_line = lineno


def _split_names(path: str, lineno: int, value: str) -> list[str]:
    """VARS column names: comma separated if there is a comma, else blank separated."""
    if "," in value:
        names = [name.strip(_WS) for name in value.split(",")]
    else:
        names = [name for name in re.split(r"[ \t\f\v]+", value) if name]
    if not names:
        _fail(path, f"line {lineno}", "VARS line lists no columns")
    if any(not name for name in names):
        _fail(path, f"line {lineno}", "VARS line has an empty column name (two commas in a row?)")
    return names


# ----------------------------------------------------------------- columns


def _classify_columns(path: str, header: _Header) -> _Columns:
    where = f"line {header.vars_line}"
    angles: dict[str, int] = {}
    channel_idx: list[int] = []
    seen: dict[str, int] = {}
    for index, name in enumerate(header.columns):
        lower = name.lower()
        if lower in seen:
            _fail(path, where, f"VARS names column {_show(name)} twice")
        seen[lower] = index
        canon = _ANGLE_ALIAS.get(lower)
        if canon is None:
            channel_idx.append(index)
            continue
        if canon in angles:
            other = header.columns[angles[canon]]
            _fail(path, where, f"VARS columns {_show(other)} and {_show(name)} both give {canon}")
        angles[canon] = index
    for required in ("theta_i", "theta_s", "phi_s"):
        if required not in angles:
            aliases = "/".join(_ANGLE_NAMES[required])
            _fail(path, where, f"VARS has no {required} column (accepted names: {aliases})")
    if not channel_idx:
        _fail(path, where, "VARS lists no value column after the angles")
    if len(channel_idx) > MAX_CHANNELS:
        _fail(
            path, where, f"VARS lists {len(channel_idx)} value columns; a table holds at most {MAX_CHANNELS} channels"
        )
    names = [header.columns[i] for i in channel_idx]
    kind, order, wavelengths = _channel_kind(path, where, names)
    return _Columns(angles, [channel_idx[i] for i in order], kind, wavelengths)


def _channel_kind(path: str, where: str, names: list[str]) -> tuple[str, list[int], np.ndarray | None]:
    """(channel_kind, order of the channel columns, wavelengths or None)."""
    if len(names) == 1:
        return "mono", [0], None
    lower = [name.lower() for name in names]
    for kind, expected in _TRISTIMULUS:
        if sorted(lower) == sorted(expected):
            return kind, [lower.index(e) for e in expected], None
    wavelengths = [_wavelength(name) for name in names]
    if all(w is not None for w in wavelengths):
        return _spectral_order(path, where, names, [w for w in wavelengths if w is not None])
    _fail(
        path,
        where,
        f"cannot tell what the value columns {', '.join(names)} are: expected "
        "R G B, X Y Z, a single BRDF column or wavelength columns such as 450, 450nm, brdf_450",
    )


def _wavelength(name: str) -> float | None:
    match = _WAVELENGTH_RE.fullmatch(name.strip())
    return float(match.group(1)) if match else None


def _spectral_order(
    path: str, where: str, names: list[str], wavelengths: list[float]
) -> tuple[str, list[int], np.ndarray]:
    order = sorted(range(len(names)), key=lambda i: wavelengths[i])
    sorted_wl = np.array([wavelengths[i] for i in order], dtype=np.float64)
    if sorted_wl[0] <= 0.0:
        _fail(path, where, f"wavelength column {_show(names[order[0]])} is not a positive wavelength")
    repeats = np.flatnonzero(np.diff(sorted_wl) <= 0.0)
    if repeats.size:
        i = int(repeats[0])
        _fail(
            path, where, f"columns {_show(names[order[i]])} and {_show(names[order[i + 1]])} give the same wavelength"
        )
    return "spectral", order, sorted_wl


# -------------------------------------------------------------------- rows


def _data_rows(lines: list[str], start: int) -> list[tuple[int, str]]:
    """(1-based line number, stripped text) of every non-blank, non-comment line after VARS."""
    rows = []
    for index in range(start, len(lines)):
        line = lines[index].strip(_WS)
        if line and not line.startswith("#"):
            rows.append((index + 1, line))
    return rows


def _check_row_count(path: str, header: _Header, rows: list[tuple[int, str]]) -> None:
    """Compare NUM_POINTS with the rows present, before anything of that size exists."""
    if not rows:
        _fail(path, f"line {header.vars_line}", "no data rows after the VARS line")
    if header.num_points is None or header.num_points == len(rows):
        return
    hint = " (file truncated?)" if len(rows) < header.num_points else ""
    _fail(
        path,
        "NUM_POINTS",
        f"NUM_POINTS on line {header.num_points_line} announces "
        f"{header.num_points} data rows but the file has {len(rows)} "
        f"(last data row on line {rows[-1][0]}){hint}",
    )


def _parse_rows(path: str, header: _Header, rows: list[tuple[int, str]], nonfinite: bool = False) -> np.ndarray:
    """All rows as float64 (n, columns); every token is checked before conversion.

    Fast path: when the data hold only digits, signs, '.', 'e', commas and blanks and
    no empty comma field, Python's float grammar equals the one accepted here, so
    numpy converts directly.  Any failure (bad token, wrong row length) falls back to
    a row-by-row walk that names the offending line.  nonfinite: NaN and infinity tokens
    are numbers too (the caller reports them).
    """
    width = len(header.columns)
    block = "\n".join(line for _, line in rows)
    table = None
    if _DATA_CHARS_RE.fullmatch(block) and not _has_empty_field(block):
        table = _convert(block, len(rows), width)
    if table is None and nonfinite:
        table = _convert_with_nonfinite(rows, width)
    if table is None:
        _explain_bad_rows(path, header, rows)
    return table


def _has_empty_field(block: str) -> bool:
    """A comma at the start or end of a (stripped) row, or two commas in a row."""
    if "," not in block:
        return False
    return (
        block.startswith(",")
        or block.endswith(",")
        or ",\n" in block
        or "\n," in block
        or _DOUBLE_COMMA_RE.search(block) is not None
    )


def _convert(block: str, count: int, width: int) -> np.ndarray | None:
    """float64 (count, width), or None if a token is not a number or a row has the wrong length."""
    spaced = block.replace(",", " ")
    single_separators = "  " not in spaced and not any(c in spaced for c in "\t\f\v")
    try:
        if single_separators:  # one flat split; row lengths from the separator counts
            if any(line.count(" ") != width - 1 for line in spaced.split("\n")):
                return None
            table = np.array(spaced.split(), dtype=np.float64)
        else:
            table = np.array([line.split() for line in spaced.split("\n")], dtype=np.float64)
    except (ValueError, OverflowError):  # bad token or ragged rows
        return None
    return table.reshape(count, width) if table.size == count * width else None


def _convert_with_nonfinite(rows: list[tuple[int, str]], width: int) -> np.ndarray | None:
    """Row by row, numbers and NaN / infinity tokens; None at the first other problem."""
    table = np.empty((len(rows), width), dtype=np.float64)
    for r, (_, line) in enumerate(rows):
        tokens = _SEP_RE.split(line)
        if len(tokens) != width:
            return None
        for c, token in enumerate(tokens):
            if not (_NUMBER_RE.fullmatch(token) or _NONFINITE_RE.fullmatch(token)):
                return None
            table[r, c] = float(token)
    return table


def _collect_bad_values(
    names: list[str],
    table: np.ndarray,
    channels: list[int],
    line_numbers: np.ndarray,
    rows: list[tuple[int, str]],
    bad: BadValues,
) -> np.ndarray:
    """Lists the value columns' NaN, infinite and beyond-float32 entries in `bad`, zeroes
    them, and returns which rows had one."""
    values = table[:, channels]
    with np.errstate(invalid="ignore"):
        faulty = ~np.isfinite(values) | (np.abs(values) > _FLOAT32_MAX)
    for row, k in np.argwhere(faulty)[: BadValues.FIRST]:
        col = channels[int(k)]
        token = _SEP_RE.split(rows[int(row)][1])[col]
        bad.add({"where": f"line {int(line_numbers[row])}", "column": _column_label(names, col), "value": token})
    bad.count = int(faulty.sum())
    cols = np.asarray(channels)
    table[:, cols] = np.where(faulty, 0.0, values)
    rows_bad: np.ndarray = faulty.any(axis=1)
    return rows_bad


def _explain_bad_rows(path: str, header: _Header, rows: list[tuple[int, str]]) -> NoReturn:
    """Raise for the first row that is malformed or has the wrong number of columns."""
    width = len(header.columns)
    for lineno, line in rows:
        if _ROW_RE.fullmatch(line) is None:
            _explain_bad_row(path, header.columns, lineno, line)
        found = len(_SEP_RE.split(line))
        if found != width:
            _fail(
                path,
                f"line {lineno}",
                f"expected {width} numbers (the columns named on the VARS line {header.vars_line}), found {found}",
            )
    _fail(path, f"line {rows[0][0]}", "malformed data rows")


def _explain_bad_row(path: str, names: list[str], lineno: int, line: str) -> NoReturn:
    """Raise the most precise error for a row that is not a list of plain numbers."""
    where = f"line {lineno}"
    for index, token in enumerate(_SEP_RE.split(line)):
        column = _column_label(names, index)
        if not token:
            _fail(path, where, f"empty field in {column} (two separators in a row)")
        if _NUMBER_RE.fullmatch(token):
            continue
        lowered = token.lower()
        if "nan" in lowered:
            _fail(path, where, f"NaN value {_show(token)} in {column}")
        if "inf" in lowered:
            _fail(path, where, f"infinite value {_show(token)} in {column}")
        _fail(path, where, f"{_show(token)} in {column} is not a number")
    _fail(path, where, f"malformed data row {_show(line)}")


def _column_label(names: list[str], index: int) -> str:
    if index < len(names):
        return f"column {index + 1} ({names[index]})"
    return f"column {index + 1} (more columns than VARS names)"


def _check_finite(
    path: str, names: list[str], table: np.ndarray, line_numbers: np.ndarray, rows: list[tuple[int, str]]
) -> None:
    """Numbers like 1e999 parse as inf: reject them with their line."""
    bad = ~np.isfinite(table)
    if not bad.any():
        return
    row, col = (int(i) for i in np.argwhere(bad)[0])
    token = _SEP_RE.split(rows[row][1])[col]
    _fail(
        path, f"line {line_numbers[row]}", f"value {_show(token)} in {_column_label(names, col)} overflows to infinity"
    )


def _check_channels_fit_float32(
    path: str, names: list[str], table: np.ndarray, channels: list[int], line_numbers: np.ndarray
) -> None:
    limit = float(np.finfo(np.float32).max)
    bad = np.abs(table[:, channels]) > limit
    if not bad.any():
        return
    row, k = (int(i) for i in np.argwhere(bad)[0])
    col = channels[k]
    _fail(
        path,
        f"line {line_numbers[row]}",
        f"value {table[row, col]:g} in {_column_label(names, col)} is too large for float32",
    )


def _check_angle_ranges(
    path: str, names: list[str], table: np.ndarray, angles: dict[str, int], line_numbers: np.ndarray
) -> None:
    """theta in [0, pi/2], phi in [-2 pi, 2 pi] (radians), each with ANGLE_TOL slack."""
    limits = {
        "theta_i": (0.0, HALF_PI),
        "theta_s": (0.0, HALF_PI),
        "phi_i": (-TWO_PI, TWO_PI),
        "phi_s": (-TWO_PI, TWO_PI),
    }
    first_bad: tuple[int, int, str] | None = None
    for canon, col in angles.items():
        low, high = limits[canon]
        bad = np.flatnonzero((table[:, col] < low - ANGLE_TOL) | (table[:, col] > high + ANGLE_TOL))
        if bad.size and (first_bad is None or bad[0] < first_bad[0]):
            first_bad = (int(bad[0]), col, canon)
    if first_bad is None:
        return
    row, col, canon = first_bad
    value = table[row, col]
    span = "[0, pi/2]" if canon.startswith("theta") else "[-2 pi, 2 pi]"
    hint = " (angles must be in radians; this looks like degrees)" if abs(value) > TWO_PI else ""
    _fail(path, f"line {line_numbers[row]}", f"{_column_label(names, col)} = {value:g} is outside {span}{hint}")


# -------------------------------------------------------------------- grid


def _grid_axes(table: np.ndarray, angles: dict[str, int]) -> tuple[str, list[_Axis]]:
    """Choose the parametrization and build its axes (values + per-row labels)."""
    theta_i = np.clip(table[:, angles["theta_i"]], 0.0, HALF_PI)
    theta_o = np.clip(table[:, angles["theta_s"]], 0.0, HALF_PI)
    phi_o = table[:, angles["phi_s"]]
    phi_i = table[:, angles["phi_i"]] if "phi_i" in angles else np.zeros_like(phi_o)
    theta_i_axis = _merged_axis("theta_i", theta_i)
    theta_o_axis = _merged_axis("theta_o", theta_o)
    if _is_isotropic(theta_i_axis.labels, phi_i):
        phi_d_axis = _merged_axis("phi_d", _fold_phi_d(phi_o - phi_i))
        return "isotropic", [theta_i_axis, theta_o_axis, phi_d_axis]
    phi_i_axis = _merged_axis("phi_i", _normalise_phi(phi_i))
    phi_o_axis = _merged_axis("phi_o", _normalise_phi(phi_o))
    return "anisotropic", [theta_i_axis, phi_i_axis, theta_o_axis, phi_o_axis]


def _is_isotropic(theta_i_labels: np.ndarray, phi_i: np.ndarray) -> bool:
    """True when every incidence angle theta_i is measured at a single phi_i.

    Then the rows can only depend on phi_d = |phi_s - phi_i| and nothing is lost by
    storing (theta_i, theta_o, phi_d); with several phi_i per theta_i the file is
    anisotropic.
    """
    if np.all(np.abs(phi_i) <= PHI_ZERO_TOL):
        return True
    phi_i_labels = _merge(_normalise_phi(phi_i))[1]
    pairs = np.unique(np.stack([theta_i_labels, phi_i_labels], axis=1), axis=0)
    return len(pairs) == int(theta_i_labels.max()) + 1


def _normalise_phi(phi: np.ndarray) -> np.ndarray:
    """Into [0, 2 pi); values within ANGLE_TOL below 2 pi become 0."""
    wrapped: np.ndarray = np.mod(phi, TWO_PI)
    wrapped[wrapped >= TWO_PI - ANGLE_TOL] = 0.0
    return wrapped


def _fold_phi_d(delta: np.ndarray) -> np.ndarray:
    """|delta| folded into [0, pi] (exact for 0 <= |delta| <= pi)."""
    folded: np.ndarray = np.mod(np.abs(delta), TWO_PI)
    folded = np.where(folded > math.pi, TWO_PI - folded, folded)
    return np.clip(folded, 0.0, math.pi, out=folded)


def _merged_axis(name: str, values: np.ndarray) -> _Axis:
    axis_values, labels = _merge(values)
    return _Axis(name, axis_values, labels)


def _merge(values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cluster sorted values whose gaps are <= ANGLE_TOL.

    Returns (one value per cluster, strictly increasing; per-value cluster index).
    Each cluster is represented by its (lower) median member, an actual file value.
    """
    order = np.argsort(values, kind="stable")
    ordered = values[order]
    starts_cluster = np.ones(len(ordered), dtype=bool)
    starts_cluster[1:] = np.diff(ordered) > ANGLE_TOL
    cluster = np.cumsum(starts_cluster) - 1
    starts = np.flatnonzero(starts_cluster)
    ends = np.append(starts[1:], len(ordered))
    representatives = ordered[(starts + ends - 1) // 2].astype(np.float64)
    labels = np.empty(len(ordered), dtype=np.int64)
    labels[order] = cluster
    return representatives, labels


def _grid_positions(path: str, axes: list[_Axis], line_numbers: np.ndarray) -> np.ndarray:
    """Flat C-order grid index of every row; raises unless each grid point occurs once."""
    for axis in axes:
        if len(axis.values) < 2:
            _fail(
                path,
                axis.name,
                f"the {axis.name} axis has only one value "
                f"({axis.values[0]:.6g} rad); a table needs at least 2 per axis",
            )
    labels = np.stack([axis.labels for axis in axes], axis=1)
    order = np.lexsort(labels.T[::-1])  # stable: equal points keep file order
    ordered = labels[order]
    _check_no_duplicates(path, axes, ordered, order, line_numbers)
    dims = [len(axis.values) for axis in axes]
    total = math.prod(dims)
    if total != len(labels):
        missing = _first_missing(ordered, dims)
        _fail(
            path,
            "grid",
            f"missing grid point {_describe(axes, missing)}: {len(labels)} rows "
            f"for a {' x '.join(map(str, dims))} grid of {total} points; {NOT_A_GRID}",
        )
    flat: np.ndarray = np.ravel_multi_index(tuple(labels.T), dims)
    return flat


def _check_no_duplicates(
    path: str, axes: list[_Axis], ordered: np.ndarray, order: np.ndarray, line_numbers: np.ndarray
) -> None:
    same_as_previous = np.all(ordered[1:] == ordered[:-1], axis=1)
    if not same_as_previous.any():
        return
    positions = np.flatnonzero(same_as_previous) + 1
    offenders = order[positions]
    pick = int(np.argmin(offenders))
    position = int(positions[pick])
    first = position
    while first > 0 and same_as_previous[first - 1]:
        first -= 1
    row, earlier = int(offenders[pick]), int(order[first])
    point = tuple(int(i) for i in ordered[position])
    _fail(
        path,
        f"line {line_numbers[row]}",
        f"duplicate grid point {_describe(axes, point)} (already given on line {line_numbers[earlier]}); {NOT_A_GRID}",
    )


def _first_missing(ordered: np.ndarray, dims: list[int]) -> tuple[int, ...]:
    """First C-order grid point absent from the sorted, duplicate-free label rows."""
    count = len(ordered)
    expected = _unravel(np.arange(count, dtype=np.int64), dims)
    mismatch = np.flatnonzero(np.any(ordered != expected, axis=1))
    first = int(mismatch[0]) if mismatch.size else count
    return tuple(int(i) for i in _unravel(np.array([first], dtype=np.int64), dims)[0])


def _unravel(flat: np.ndarray, dims: list[int]) -> np.ndarray:
    """np.unravel_index without forming prod(dims) (which may overflow); flat < len(rows)."""
    digits = np.empty((len(flat), len(dims)), dtype=np.int64)
    rest = flat.copy()
    for k in range(len(dims) - 1, -1, -1):
        digits[:, k] = rest % dims[k]
        rest //= dims[k]
    return digits


def _describe(axes: list[_Axis], point: tuple[int, ...]) -> str:
    return "(" + ", ".join(f"{a.name}={a.values[i]:.6g}" for a, i in zip(axes, point, strict=True)) + ")"


# -------------------------------------------------------------- provenance


def _provenance(path: str, header: _Header) -> str:
    """'ASTM E1392-96; SOURCE=...; DATE=...; file=name' from the header present."""
    parts = [_clean(header.magic)] if header.magic else []
    for key, value in header.keywords:
        parts.append(f"{key}={_clean(value)}" if value else key)
    parts.append(f"file={os.path.basename(path)}")
    return "; ".join(parts)


def _clean(text: str) -> str:
    printable = "".join(ch if ch.isprintable() else "?" for ch in text.strip())
    if len(printable) > _PROVENANCE_VALUE_MAX:
        printable = printable[: _PROVENANCE_VALUE_MAX - 3] + "..."
    return printable
