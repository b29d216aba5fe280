"""Every supported table file becomes a patina.Brdf: the format is recognised by its
content first (magic bytes, header keywords), then by its extension."""

from __future__ import annotations

import os

from patina.errors import FormatError
from patina.native import _core
from patina.table.brdf import Brdf
from patina.table.formats.astm import read_astm
from patina.table.formats.csv_table import read_csv
from patina.table.formats.mdl import MAGIC as MBSDF_MAGIC
from patina.table.formats.mdl import read_mdl
from patina.table.formats.rgl import read_rgl
from patina.table.formats.tabledata import table_from_data
from patina.table.formats.tensor_file import MAGIC as TENSOR_FILE_MAGIC
from patina.table.formats.utia import read_utia
from patina.table.formats.window_xml import read_window_xml
from patina.table.formats.zemax import read_zemax

PTAB_MAGIC = b"PTAB\r\n\x1a\n"
SUPPORTED = (
    ".ptab (Patina), MERL .binary, ASTM E1392 text (.astm/.txt/.brdf/.dat), CSV (.csv), RGL .bsdf "
    "(tensor_file), NVIDIA MDL .mbsdf, UTIA .bin, LBNL WINDOW / Radiance BSDF XML (.xml, Klems) "
    "or Zemax / LightTools tabular BSDF text (.bsdf, .zmx.bsdf)"
)
# Readers of formats Patina only imports: path -> TableData
IMPORTERS = {"rgl": read_rgl, "mdl": read_mdl, "utia": read_utia, "window_xml": read_window_xml, "zemax": read_zemax}
SIGNATURES = ((TENSOR_FILE_MAGIC, "rgl"), (MBSDF_MAGIC, "mdl"))
# by extension: UTIA has no signature; for the others the reader reports the wrong one
EXTENSIONS = {".bsdf": "rgl", ".mbsdf": "mdl", ".bin": "utia", ".xml": "window_xml"}


def _zemax_header(head: bytes) -> bool:
    """Zemax tabular BSDF text: its keywords at the start of lines (Zemax and RGL share .bsdf)."""
    words = {line.split()[0].lower() for line in head.decode("latin-1").splitlines() if line.split()}
    return {"symmetry", "scattertype", "angleofincidence"} <= words


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
    for magic, kind in SIGNATURES:
        if head.startswith(magic):
            return kind
    if b"<WindowElement" in head:  # after an XML declaration, comments or a stray line
        return "window_xml"
    if _zemax_header(head):
        return "zemax"
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ptab":
        return "ptab"  # the reader will report the wrong magic
    if ext in EXTENSIONS:
        return EXTENSIONS[ext]
    if ext == ".binary":
        return "merl"
    if ext == ".csv":
        return "csv"
    text = head.decode("latin-1").lower()
    if "astm" in text[:200] or "\nvars" in text or text.startswith("vars"):
        return "astm"
    if ext in (".astm", ".txt", ".brdf", ".dat"):
        return "astm"
    raise FormatError(path, "", f"unrecognised file: expected {SUPPORTED}")


def read_any(path: str | os.PathLike) -> Brdf:
    """Any supported file as a Brdf (SUPPORTED lists them)."""
    path = os.fspath(path)
    kind = detect_format(path)
    if kind == "ptab":
        return Brdf(_core.read_ptab(path), path, "ptab")
    if kind == "merl":
        return Brdf(_core.read_merl(path), path, "merl")
    if kind in IMPORTERS:
        data = IMPORTERS[kind](path)
    elif kind == "csv":
        data = read_csv(path)
    else:
        data = read_astm(path, resample=True)  # scattered measurements onto a grid, error reported
    try:
        table = table_from_data(data)
    except ValueError as e:
        raise FormatError(path, "table", str(e)) from None
    return Brdf(table, path, kind)


load_brdf = read_any  # the public name (patina.load_brdf)
