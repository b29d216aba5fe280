"""File names as the workbench shows them and hands them to the C++ engine.

A Linux file name is bytes; Python holds the bytes that are not UTF-8 as lone surrogates
(os.fsdecode), which print, encode and cross into C++ only with care: `printable` gives the
name a message, a CSV or a page can show (those bytes as \\xNN), and `engine_path` a path
the engine's UTF-8 string arguments accept for any file. `not_a_regular_file` tells what
a name points to before anything opens it."""

from __future__ import annotations

import contextlib
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator

from patina.errors import FormatError


def printable(path: str | os.PathLike) -> str:
    """`path` with every byte that is not UTF-8 shown as \\xNN: always encodes as UTF-8."""
    return os.fsencode(path).decode("utf-8", "backslashreplace")


def is_utf8(path: str | os.PathLike) -> bool:
    try:
        os.fsencode(path).decode("utf-8")
    except UnicodeDecodeError:
        return False
    return True


@contextlib.contextmanager
def engine_path(path: str) -> Iterator[str]:
    """`path` itself when its name is UTF-8; else, meanwhile, a symbolic link to it with a
    UTF-8 name and the same extension (the formats go by it), in a private temporary folder."""
    if is_utf8(path):
        yield path
        return
    folder = tempfile.mkdtemp(prefix="patina-name-")
    try:
        alias = os.path.join(folder, "file" + printable(os.path.splitext(path)[1]))
        os.symlink(os.path.abspath(path), alias)
        yield alias
    finally:
        shutil.rmtree(folder, ignore_errors=True)


SPECIAL_FILES = (
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
    (stat.S_ISDIR, "a folder"),
)


def not_a_regular_file(path: str | os.PathLike) -> str:
    """What `path` is when it is not a regular file (links followed), else "". Asked of the
    file system without opening it: opening a FIFO waits for a writer forever, and reading
    /dev/zero never ends."""
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        return f"cannot be read: {e.strerror}"
    if stat.S_ISREG(mode):
        return ""
    kind = next((what for test, what in SPECIAL_FILES if test(mode)), "not a regular file")
    return kind + (", through a symbolic link" if os.path.islink(path) else "")


def refuse_special_file(path: str) -> None:
    """FormatError at once for a FIFO, a device or a socket given as an input file (a missing
    one is left to the reader, which says so in its words)."""
    kind = not_a_regular_file(path) if os.path.exists(path) else ""
    if kind and kind != "a folder":
        raise FormatError(printable(path), "", f"not a regular file ({kind}): only files are read")
