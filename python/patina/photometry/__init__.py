"""Photometric files (IES LM-63, EULUMDAT) read into one model, `Photometry`
(docs/luminaires.md): `read_photometry(path)` picks the reader by content, then extension."""

from __future__ import annotations

import os

from ..errors import FormatError
from .angles import angles_of, direction_of
from .ies import read_ies
from .ldt import read_ldt
from .model import Opening, Photometry, Tilt

__all__ = [
    "FormatError",
    "Opening",
    "Photometry",
    "Tilt",
    "angles_of",
    "direction_of",
    "read_ies",
    "read_ldt",
    "read_photometry",
]


def read_photometry(path: str | os.PathLike) -> Photometry:
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
