"""One entry point for photometric files: the reader is picked by extension, then content."""

from __future__ import annotations

import os

from patina.errors import FormatError
from patina.photometry.ies import read_ies
from patina.photometry.ldt import read_ldt
from patina.photometry.model import Photometry


def read_photometry(path: str | os.PathLike) -> Photometry:
    """An IES LM-63 or EULUMDAT file as Photometry; FormatError naming the file otherwise."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext == ".ldt":
        return read_ldt(path)
    if ext == ".ies":
        return read_ies(path)
    try:
        with open(path, "rb") as f:
            head = f.read(4096).decode("latin-1")
    except OSError:
        return read_ies(path)  # the reader reports the problem
    if head.lstrip().upper().startswith("IES") or "TILT=" in head.upper():
        return read_ies(path)
    raise FormatError(path, "", "not a photometric file: expected an IES LM-63 (.ies) or EULUMDAT (.ldt) file")
