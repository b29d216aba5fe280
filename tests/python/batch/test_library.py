"""patina.batch.library: what is taken as a table. Only regular files: a FIFO, a device, a
link to one are skipped with a notice at once (reading them waits forever or never ends);
file names that are not UTF-8 are tables like any other."""

from __future__ import annotations

import csv
import os
import shutil

from batch_library import GOOD, QUICK, write_plastic

from patina.batch import IN_PROCESS, run_batch
from patina.batch.library import find_tables

VALIDATE = QUICK.__class__(steps=("validate",))


def test_special_files_are_skipped_with_a_notice(tmp_path):
    """Before: a FIFO hung the batch forever; a link to /dev/zero hashed an endless stream."""
    folder = tmp_path / "library"
    folder.mkdir()
    write_plastic(str(folder / "red.ptab"), (0.5, 0.1, 0.1), 0.2)
    os.mkfifo(folder / "fifo.ptab")
    os.symlink("/dev/zero", folder / "zero.ptab")
    os.symlink("/dev/urandom", folder / "random.binary")
    tables, skipped = find_tables(str(folder))
    assert [t.name for t in tables] == ["red.ptab"]
    assert dict(skipped) == {
        "fifo.ptab": "not a regular file (a FIFO)",
        "random.binary": "not a regular file (a character device, through a symbolic link)",
        "zero.ptab": "not a regular file (a character device, through a symbolic link)",
    }


def test_a_name_that_is_not_utf8_is_processed_and_reported(tmp_path):
    """Before: the task failed ("incompatible function arguments") and summary.csv could not be
    written ("surrogates not allowed"): exit 2, no index.html."""
    folder = tmp_path / "library"
    folder.mkdir()
    name = os.fsdecode(b"caf\xe9 \xff.ptab")  # Latin-1 bytes: not UTF-8
    write_plastic(str(folder / GOOD[0]), (0.5, 0.1, 0.1), 0.2)
    shutil.copy(folder / GOOD[0], os.path.join(folder, name))
    out = str(tmp_path / "out")
    lines: list[str] = []
    summary = run_batch(str(folder), out, VALIDATE, scheduler=IN_PROCESS, progress=False, say=lines.append)
    assert summary["counts"] == {**summary["counts"], "ok": 2, "failed": 0}
    with open(os.path.join(out, "summary.csv"), encoding="utf-8") as f:  # UTF-8 text, the bytes escaped
        rows = {row["name"]: row for row in csv.DictReader(f)}
    assert set(rows) == {GOOD[0], "caf\\xe9 \\xff.ptab"}
    assert rows["caf\\xe9 \\xff.ptab"]["validation"] == "passed"
    page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
    assert "caf\\xe9 \\xff.ptab" in page
    assert os.path.isfile(os.path.join(out, "materials", name, "validate.json"))


def test_other_xml_and_bin_files_are_skipped_by_their_content(tmp_path):
    """A library's settings .xml or data .bin is not a table: skipped with a notice, not a failed task."""
    from repo_paths import ROOT

    folder = tmp_path / "lib"
    folder.mkdir()
    write_plastic(str(folder / "red.ptab"), (0.5, 0.1, 0.1), 0.2)
    shutil.copy(os.path.join(ROOT, "materials", "radiance", "blindsT3.xml"), folder / "blinds.xml")
    (folder / "settings.xml").write_text("<?xml version='1.0'?><settings/>")
    (folder / "capture.bin").write_bytes(bytes(4096))
    tables, skipped = find_tables(str(folder))
    assert [t.name for t in tables] == ["blinds.xml", "red.ptab"]
    assert dict(skipped) == {
        "capture.bin": "not a table: a .bin file without exactly 1990656 bytes (a UTIA BRDF)",
        "settings.xml": "not a table: a .xml file without a <WindowElement> (a BSDF XML document)",
    }
