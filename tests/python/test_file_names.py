"""patina.file_names: names that are not UTF-8 shown and handed to the engine; special files
refused before anything opens them."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patina.errors import FormatError
from patina.file_names import engine_path, not_a_regular_file, printable, refuse_special_file
from patina.table import load_brdf

NAME_BYTES = st.binary(min_size=1, max_size=40).filter(
    lambda b: b"/" not in b and b"\0" not in b and b not in (b".", b"..")
)


@settings(max_examples=200, deadline=None)
@given(NAME_BYTES)
def test_printable_is_utf8_and_keeps_utf8_names_as_they_are(name):
    shown = printable(os.fsdecode(name))
    shown.encode("utf-8")  # never "surrogates not allowed"
    try:
        assert shown == name.decode("utf-8")
    except UnicodeDecodeError:
        assert "\\x" in shown


def test_the_engine_reads_a_table_whose_name_is_not_utf8(tmp_path, bundled_ptab):
    """Before: "read_ptab(): incompatible function arguments"."""
    path = os.path.join(tmp_path, os.fsdecode(b"red \xff.ptab"))
    with open(bundled_ptab, "rb") as src, open(path, "wb") as dst:
        dst.write(src.read())
    with engine_path(path) as readable:
        assert load_brdf(readable).info()["channels"] == load_brdf(bundled_ptab).info()["channels"]
    assert os.listdir(tmp_path) == [os.path.basename(path)]  # the alias is gone
    with engine_path(bundled_ptab) as readable:
        assert readable == bundled_ptab


def test_special_files_are_named_without_being_opened(tmp_path):
    os.mkfifo(tmp_path / "fifo.ptab")
    os.symlink("/dev/zero", tmp_path / "zero.ptab")
    assert not_a_regular_file(tmp_path / "fifo.ptab") == "a FIFO"
    assert not_a_regular_file(tmp_path / "zero.ptab") == "a character device, through a symbolic link"
    with pytest.raises(FormatError, match="not a regular file"):
        refuse_special_file(str(tmp_path / "fifo.ptab"))
    refuse_special_file(str(tmp_path / "missing.ptab"))  # left to the reader's own message


def test_info_on_a_fifo_refuses_at_once(tmp_path):
    """Before: `patina info` waited for a writer forever."""
    os.mkfifo(tmp_path / "fifo.ptab")
    done = subprocess.run(
        [sys.executable, "-m", "patina.cli", "info", str(tmp_path / "fifo.ptab")],
        check=False, capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 2
    assert done.stderr == f"patina: error: {tmp_path / 'fifo.ptab'}: not a regular file (a FIFO): only files are read\n"
