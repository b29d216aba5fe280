"""Every supported table file becomes a patina.Brdf: the format is recognised by its
content first (magic bytes, header keywords), then by its extension."""

from __future__ import annotations

import os

import numpy as np

from patina.errors import FormatError
from patina.native import _core
from patina.table.brdf import Brdf
from patina.table.formats.astm import read_astm
from patina.table.formats.csv_table import read_csv
from patina.table.formats.tabledata import TableData

PTAB_MAGIC = b"PTAB\r\n\x1a\n"


def detect_format(path: str) -> str:
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
    except IsADirectoryError:
        raise FormatError(path, "", "is a directory, not a file") from None
    except OSError as e:
        raise FormatError(path, "", f"cannot open: {e.strerror}") from None
    if head.startswith(PTAB_MAGIC):
        return "ptab"
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ptab":
        return "ptab"  # the reader will report the wrong magic
    if ext == ".binary":
        return "merl"
    if ext == ".csv":
        return "csv"
    text = head.decode("latin-1").lower()
    if "astm" in text[:200] or "\nvars" in text or text.startswith("vars"):
        return "astm"
    if ext in (".astm", ".txt", ".brdf", ".dat"):
        return "astm"
    raise FormatError(path, "", "unrecognised file: expected .ptab (Patina), MERL .binary, or ASTM E1392 text")


def table_from_data(data: TableData) -> _core.Table:
    """Turns an importer's TableData into a native (checked, immutable) table."""
    channels = int(data.values.shape[-1])
    symmetry = 0
    if "reciprocity" in data.symmetry:
        symmetry |= _core.SYM_RECIPROCITY
    if "phi_mirror" in data.symmetry:
        symmetry |= _core.SYM_PHI_MIRROR
    valid = None if data.mask is None else np.ascontiguousarray(data.mask, dtype=np.uint8)
    return _core.Table.from_arrays(
        data.parametrization,
        [np.ascontiguousarray(a, dtype=np.float32) for a in data.axes],
        np.ascontiguousarray(data.values, dtype=np.float32).reshape(-1),
        channels,
        data.channel_kind,
        None if data.wavelengths is None else np.ascontiguousarray(data.wavelengths, dtype=np.float32),
        valid,
        symmetry,
        data.units,
        data.provenance,
    )


def read_any(path: str | os.PathLike) -> Brdf:
    """Any supported file as a Brdf: .ptab (native), MERL .binary, ASTM E1392 text or CSV."""
    path = os.fspath(path)
    kind = detect_format(path)
    if kind == "ptab":
        return Brdf(_core.read_ptab(path), path, "ptab")
    if kind == "merl":
        return Brdf(_core.read_merl(path), path, "merl")
    if kind == "csv":
        data = read_csv(path)
    else:
        data = read_astm(path, resample=True)  # scattered measurements onto a grid, error reported
    try:
        table = table_from_data(data)
    except ValueError as e:
        raise FormatError(path, "table", str(e)) from None
    return Brdf(table, path, kind)


load_brdf = read_any  # the public name (patina.load_brdf)
