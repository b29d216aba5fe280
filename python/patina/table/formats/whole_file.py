"""A binary file's bytes, read whole once its size is known to be acceptable, so that a
file too large for its format is refused before any of it is read."""

from __future__ import annotations

import os

from patina.errors import FormatError


def read_whole_file(path: str, max_bytes: int, exact: int | None = None, what: str = "") -> bytes:
    """The bytes of `path`; FormatError when it cannot be opened, is larger than max_bytes,
    or (with `exact`) has any other size than `exact` (`what` names the format)."""
    try:
        with open(path, "rb") as handle:
            size = os.fstat(handle.fileno()).st_size
            if exact is not None and size != exact:
                raise FormatError(path, "file", f"{size} bytes: {what} has exactly {exact}")
            if size > max_bytes:
                raise FormatError(path, "file", f"{size} bytes: larger than the {max_bytes >> 20} MiB accepted")
            return handle.read()
    except OSError as e:
        raise FormatError(path, "", f"cannot open: {e.strerror}") from None
