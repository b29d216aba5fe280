"""Outputs written whole or not at all: to a temporary file beside the target, then renamed
over it. A failed write removes the temporary file and leaves the target as it was."""

from __future__ import annotations

import contextlib
import errno
import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path

from patina.file_names import printable


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


NEW_FILE_MODE = 0o666 & ~_umask()  # read once, at import: changing the umask is process-wide


def _error(code: int | None, message: str) -> OSError:
    """An OSError whose text is `message` alone (OSError(errno, text) would print "[Errno n]")."""
    e = OSError(message)
    e.errno = code
    return e


def _named_error(shown: str, tmp: str, e: OSError) -> OSError:
    """`e` as the user should read it: about the path they gave, not our hidden temporary file.
    An error without a file name (ENOSPC from write(), EIO from fsync) is named too."""
    if e.strerror:
        return _error(e.errno, f"{shown}: cannot write: {e.strerror}")
    text = str(e).replace(tmp, shown) if tmp else str(e)
    return _error(e.errno, text if shown in text else f"{shown}: cannot write: {text}")


def _sync(tmp: str) -> None:
    """The temporary file's data on the disk before it is renamed: a file system that reports
    a full disk late (delayed allocation, NFS) reports it here, not after "wrote"."""
    fd = os.open(tmp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: another user's process, alive
        return True
    return True


def _remove_dead(parent: str, names: list[str], temporary: re.Pattern) -> None:
    """The names that are `temporary`'s (group 1: the writer's pid) of a dead writer, removed."""
    for name in names:
        m = temporary.fullmatch(name)
        if m and not _alive(int(m.group(1))):
            with contextlib.suppress(OSError):
                os.unlink(os.path.join(parent, name))


def remove_stale_temporaries(path: Path) -> None:
    """Removes the temporaries of `path` whose writer died mid-write (SIGKILL, a crash: no
    handler ran to remove them). Their names carry the writer's pid; a live writer's stay."""
    folder = str(path.parent or ".")
    try:
        names = os.listdir(folder)
    except OSError:
        return  # creating the temporary reports the problem
    _remove_dead(folder, names, re.compile(rf"\.{re.escape(path.stem)}\.p(\d+)\.\w+\.tmp{re.escape(path.suffix)}"))


def remove_dead_temporaries(folder: str) -> None:
    """Every temporary under `folder` (all depths) whose writer is dead: after worker processes
    were killed mid-write (`patina batch` aborted), where no later write beside them would."""
    for parent, _, names in os.walk(folder):
        _remove_dead(parent, names, re.compile(r"\..*\.p(\d+)\.\w+\.tmp(\.[^.]*)?"))


def _temporary(path: Path) -> str:
    remove_stale_temporaries(path)
    prefix = f".{path.stem}.p{os.getpid()}."  # the pid: remove_stale_temporaries tells a dead writer's
    fd, tmp = tempfile.mkstemp(prefix=prefix, suffix=f".tmp{path.suffix}", dir=path.parent or ".")
    os.close(fd)
    return tmp


def atomic_output(path: str | os.PathLike, write: Callable[[str], None]) -> None:
    """Run `write(temporary_path)` on a temporary file beside `path` (same extension), then
    rename it over `path`. An OSError names `path` as given, never the temporary file."""
    shown = printable(path)
    path = Path(path)
    tmp = ""
    try:
        tmp = _temporary(path)
        write(tmp)
        _sync(tmp)
        os.chmod(tmp, NEW_FILE_MODE)  # mkstemp makes it private; give it an ordinary file's mode
        os.replace(tmp, path)
    except OSError as e:
        if tmp and os.path.exists(tmp):
            os.unlink(tmp)
        raise _named_error(shown, tmp, e) from None
    except BaseException:
        if tmp and os.path.exists(tmp):
            os.unlink(tmp)
        raise


def check_writable(path: str | os.PathLike) -> None:
    """Raises OSError naming `path` unless an output can be written there: checked before a
    long job starts, so an unwritable output is reported in a second, not after the work.

    The path must not be a directory; if its folder exists a temporary file is created and
    removed there (the real test: permissions, read-only mounts, a full inode table); a
    folder yet to be made needs its nearest existing ancestor to be a writable directory."""
    shown = printable(path)
    p = Path(os.path.abspath(path))
    if p.is_dir():
        raise _error(errno.EISDIR, f"{shown}: cannot write: is a directory")
    if p.parent.is_dir():
        try:
            os.unlink(_temporary(p))
        except OSError as e:
            raise _named_error(shown, "", e) from None
        return
    ancestor = p.parent
    while not ancestor.exists() and ancestor != ancestor.parent:
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise _error(errno.ENOTDIR, f"{shown}: cannot write: {ancestor} is not a directory")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise _error(errno.EACCES, f"{shown}: cannot write: {ancestor} is not writable")


def write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """`data` as the file `path`, written atomically; its size checked once written."""

    def write(tmp: str) -> None:
        with open(tmp, "wb") as f:
            f.write(data)
        if os.path.getsize(tmp) != len(data):  # cannot happen on a POSIX file system; never rename a short file
            raise OSError(f"{tmp}: {os.path.getsize(tmp)} of {len(data)} bytes written")

    atomic_output(path, write)


def write_text(path: str | os.PathLike, text: str) -> None:
    """A UTF-8 text file, written atomically."""
    write_bytes(path, text.encode("utf-8"))
