"""CSV measurements: a header row naming the columns, then one measurement per row.

The columns are those of ASTM E1392's VARS line (theta_i, phi_i, theta_s / theta_o,
phi_s / phi_o in radians; R G B, X Y Z, wavelength-named or a single value column), so
the file is read by the ASTM reader with its header row taken as VARS: the same
checks, the same grid detection, and scattered rows resampled onto a grid. Line
numbers in messages are the CSV's own.
"""

from __future__ import annotations

import os

from patina.errors import FormatError
from patina.table.formats.astm import parse_astm_bytes
from patina.table.formats.tabledata import TableData


def read_csv(path: str | os.PathLike[str], resample: bool = True, report_bad: bool = False) -> TableData:
    """report_bad: as read_astm's (bad values listed and masked instead of refused)."""
    name = os.fspath(path)
    with open(name, "rb") as handle:
        raw = handle.read()
    lines = raw.splitlines(keepends=True)
    first = next((i for i, line in enumerate(lines) if line.strip() and not line.lstrip().startswith(b"#")), None)
    if first is None:
        raise FormatError(name, "line 1", "empty CSV: expected a header row naming the columns")
    if lines[first].lstrip()[:1].isdigit() or lines[first].lstrip()[:1] in (b"-", b"+", b"."):
        raise FormatError(name, f"line {first + 1}", "expected a header row naming the columns, found numbers")
    lines[first] = b"VARS " + lines[first].lstrip()  # the same line, so line numbers do not move
    try:
        return parse_astm_bytes(name, b"".join(lines), resample, report_bad)
    except MemoryError:
        raise FormatError(name, "file", "not enough memory to read this file") from None
