"""A folder on a full file system, for the tests of outputs written onto a full disk: a
64 KiB tmpfs mounted there (as root) and filled. Where mounting is not allowed the test is
skipped; the ENOSPC-injection tests beside it run everywhere."""

from __future__ import annotations

import contextlib
import errno
import os
import subprocess
from collections.abc import Iterator

import pytest


@contextlib.contextmanager
def full_folder(where: str) -> Iterator[str]:
    """`where`/full, a tmpfs with no byte free (the filler file takes the rest)."""
    folder = os.path.join(where, "full")
    os.makedirs(folder)
    if os.geteuid() != 0:
        pytest.skip("mounting a small tmpfs needs root")
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", folder], check=False, capture_output=True
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {mounted.stderr.decode(errors='replace').strip()}")
    try:
        with open(os.path.join(folder, "filler"), "wb", buffering=0) as f:
            with contextlib.suppress(OSError):
                while True:
                    f.write(b"\0" * 4096)
        with pytest.raises(OSError) as e, open(os.path.join(folder, "probe"), "wb") as f:
            f.write(b"\0" * 8192)
        assert e.value.errno == errno.ENOSPC
        os.unlink(os.path.join(folder, "probe"))
        yield folder
    finally:
        subprocess.run(["umount", folder], check=False)


def files_in(folder: str) -> list[str]:
    """What the folder holds besides the filler: a test expects nothing (no output, no temporary)."""
    return sorted(n for n in os.listdir(folder) if n != "filler")
