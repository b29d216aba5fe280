"""patina.atomic: outputs written whole or not at all, every failure named after the output."""

from __future__ import annotations

import errno
import os

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from full_disk import files_in, full_folder
from patina import atomic


def test_text_on_a_full_disk_names_the_file_and_leaves_nothing(tmp_path):
    with full_folder(str(tmp_path)) as full:
        target = os.path.join(full, "summary.csv")
        with pytest.raises(OSError) as e:
            atomic.write_text(target, "x" * 100_000)
        assert str(e.value) == f"{target}: cannot write: No space left on device"
        assert files_in(full) == []


def test_an_error_without_a_file_name_is_named_after_the_output(tmp_path, monkeypatch):
    """ENOSPC from write() or fsync carries no file name; the message names the output all the same."""

    def full(tmp: str) -> None:
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(atomic, "_sync", full)
    target = tmp_path / "out.json"
    target.write_text("the earlier one")
    with pytest.raises(OSError) as e:
        atomic.write_text(target, "{}")
    assert str(e.value) == f"{target}: cannot write: No space left on device"
    assert e.value.errno == errno.ENOSPC
    assert os.listdir(tmp_path) == ["out.json"]
    assert target.read_text() == "the earlier one"


def test_an_interrupt_mid_write_leaves_no_temporary(tmp_path):
    def interrupted(tmp: str) -> None:
        with open(tmp, "w") as f:
            f.write("half")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic.atomic_output(tmp_path / "a.txt", interrupted)
    assert os.listdir(tmp_path) == []


@settings(max_examples=50, deadline=None)
@given(st.binary(min_size=1, max_size=40).filter(lambda b: b"/" not in b and b"\0" not in b and b not in (b".", b"..")))
def test_any_file_name_is_written_and_printable(tmp_path_factory, name):
    """Names that are not UTF-8 (bytes a str holds as surrogates) are written, and their
    message form encodes as UTF-8 (printing it raw fails: "surrogates not allowed")."""
    folder = tmp_path_factory.mktemp("names")
    path = os.path.join(str(folder), os.fsdecode(name))
    atomic.write_text(path, "ok")
    assert os.listdir(folder.__fspath__().encode()) == [name]
    atomic.printable(path).encode("utf-8")
    assert atomic.printable(path).endswith(name.decode("utf-8", "backslashreplace"))
