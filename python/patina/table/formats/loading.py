"""Every supported table file becomes a patina.Brdf: the format is recognised by its
content first (magic bytes, header keywords), then by its extension.

A BSDF XML document holds a front and a back side: `FILE.xml#back` (or `#front`, the
default) names the side wherever a table file is named, on the command line or in Python,
unless a file of that very name exists. File names that are not UTF-8 reach the engine's
readers through a UTF-8 alias (`patina.file_names.engine_path`)."""

from __future__ import annotations

import os

from patina.errors import FormatError
from patina.file_names import engine_path, printable
from patina.native import _core
from patina.table.brdf import Brdf
from patina.table.formats.astm import read_astm
from patina.table.formats.csv_table import read_csv
from patina.table.formats.mdl import MAGIC as MBSDF_MAGIC
from patina.table.formats.mdl import read_mdl
from patina.table.formats.rgl import read_rgl
from patina.table.formats.tabledata import table_from_data
from patina.table.formats.tensor_file import MAGIC as TENSOR_FILE_MAGIC
from patina.table.formats.utia import FILE_BYTES as UTIA_BYTES
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
XML_HEAD_BYTES = 1 << 16  # how far into an .xml batch looks for <WindowElement>
SIDES = ("front", "back")  # of a BSDF XML document: FILE.xml#back
# what a file of each kind found by its extension must hold to be taken for a table when
# the content is asked to confirm it (batch: a library's other .xml or .bin files)
CONFIRMED_BY = {
    "ptab": "the .ptab magic",
    "rgl": "the tensor_file magic or Zemax keywords",
    "mdl": "the MBSDF magic",
    "window_xml": "a <WindowElement> (a BSDF XML document)",
    "utia": f"exactly {UTIA_BYTES} bytes (a UTIA BRDF)",
}
# by extension: UTIA has no signature; for the others the reader reports the wrong one
EXTENSIONS = {".bsdf": "rgl", ".mbsdf": "mdl", ".bin": "utia", ".xml": "window_xml"}


def _zemax_header(head: bytes) -> bool:
    """Zemax tabular BSDF text: its keywords at the start of lines (Zemax and RGL share .bsdf)."""
    words = {line.split()[0].lower() for line in head.decode("latin-1").splitlines() if line.split()}
    return {"symmetry", "scattertype", "angleofincidence"} <= words


def detect_format(path: str, confirm: bool = False) -> str:
    """The format's name; with `confirm`, a format found by its extension alone that has a
    signature (CONFIRMED_BY) is refused as not a table (FormatError) unless the content has it."""
    try:
        with open(path, "rb") as f:
            head = f.read(4096)
            size = os.fstat(f.fileno()).st_size
            if confirm and path.lower().endswith(".xml") and b"<WindowElement" not in head:
                head += f.read(XML_HEAD_BYTES)  # past a long comment or a writer's preamble
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
    kind = "ptab" if ext == ".ptab" else EXTENSIONS.get(ext)  # the reader reports the wrong magic
    if kind and confirm and not (kind == "utia" and size == UTIA_BYTES):
        raise FormatError(path, "", f"not a table: a {ext} file without {CONFIRMED_BY[kind]}")
    if kind:
        return kind
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


def split_side(path: str) -> tuple[str, str]:
    """(file, side) of `FILE.xml#back` / `#front`; (path, "") when no side is named or a file
    of that very name exists."""
    file, mark, side = path.rpartition("#")
    if not mark or not file or os.path.lexists(path) or not os.path.lexists(file):
        return path, ""
    if side not in SIDES:
        raise FormatError(
            printable(path), f"#{side}"[:40], "expected #front or #back (the side of a BSDF XML document)"
        )
    return file, side


def engine_read(read, path: str):
    """The engine's reader on `path`, through a UTF-8 alias when the name is not UTF-8;
    errors name the file as given."""
    with engine_path(path) as readable:
        try:
            return read(readable)
        except FormatError as e:
            if readable == path:
                raise
            raise FormatError(printable(path), e.where, e.problem.replace(readable, printable(path))) from None


def locate(given: str) -> tuple[str, str, str]:
    """(file, side, format) of a table file as named (`FILE.xml#back`)."""
    path, side = split_side(given)
    kind = detect_format(path)
    if side and kind != "window_xml":
        raise FormatError(printable(path), f"#{side}", f"a side is chosen only in BSDF XML documents, not in {kind}")
    return path, side, kind


def read_imported(kind: str, path: str, side: str):
    """The TableData of a format Patina only imports (IMPORTERS), of `side` for BSDF XML."""
    if kind == "window_xml":
        return read_window_xml(path, side=side or "front")
    return IMPORTERS[kind](path)


def read_any(path: str | os.PathLike) -> Brdf:
    """Any supported file as a Brdf (SUPPORTED lists them); `FILE.xml#back` reads the back side."""
    given = os.fspath(path)
    path, side, kind = locate(given)
    if kind == "ptab":
        return Brdf(engine_read(_core.read_ptab, path), printable(given), "ptab")
    if kind == "merl":
        return Brdf(engine_read(_core.read_merl, path), printable(given), "merl")
    if kind in IMPORTERS:
        data = read_imported(kind, path, side)
    elif kind == "csv":
        data = read_csv(path)
    else:
        data = read_astm(path, resample=True)  # scattered measurements onto a grid, error reported
    try:
        table = table_from_data(data)
    except ValueError as e:
        raise FormatError(path, "table", str(e)) from None
    return Brdf(table, printable(given), kind)  # the source shown: with its side, printable


load_brdf = read_any  # the public name (patina.load_brdf)
