"""The one loading entry point (python/patina/table/formats/loading.py) for what the other
readers leave to it: `FILE.xml#back` / `#front` naming a BSDF XML side from any command,
file names that are not UTF-8 through the engine's readers, and detection that asks the
content to confirm an extension (batch)."""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest

import patina
from patina.cli import main
from patina.errors import FormatError
from patina.table.formats.loading import detect_format
from patina.table.formats.utia import FILE_BYTES as UTIA_BYTES
from repo_paths import ROOT

BLINDS = os.path.join(ROOT, "materials", "radiance", "blindsT3.xml")  # reflection front and back


def test_a_side_is_named_after_the_file(tmp_path, capsys):
    front, back = patina.load_brdf(BLINDS), patina.load_brdf(BLINDS + "#back")
    assert "reflection back" in back.info()["provenance"] and back.source == BLINDS + "#back"
    assert np.array_equal(patina.load_brdf(BLINDS + "#front").table.values, front.table.values)
    assert not np.array_equal(back.table.values, front.table.values)
    out = str(tmp_path / "back.ptab")
    assert main(["convert", BLINDS + "#back", out]) == 0
    assert "reflection back" in patina.load_brdf(out).info()["provenance"]
    assert main(["validate", BLINDS + "#back"]) in (0, 1)  # validated, not refused
    assert main(["info", BLINDS + "#back"]) == 0 and "reflection back" in capsys.readouterr().out


def test_a_wrong_side_or_a_side_of_another_format_is_one_line(capsys):
    assert main(["info", BLINDS + "#top"]) == 2
    assert (
        capsys.readouterr().err.strip().endswith("(#top): expected #front or #back (the side of a BSDF XML document)")
    )
    ptab = os.path.join(ROOT, "materials", "red-plastic-iso.ptab")
    with pytest.raises(FormatError, match=r"\(#back\): a side is chosen only in BSDF XML documents, not in ptab"):
        patina.load_brdf(ptab + "#back")


def test_a_file_whose_name_holds_the_mark_is_read_as_named(tmp_path):
    literal = tmp_path / "plastic.ptab#back"
    shutil.copy(os.path.join(ROOT, "materials", "red-plastic-iso.ptab"), literal)
    assert patina.load_brdf(str(literal)).source_format == "ptab"


def test_the_missing_side_names_the_one_to_ask_for(tmp_path):
    text = open(BLINDS).read().replace("Reflection Front", "Transmission Front")
    path = tmp_path / "back_only.xml"
    path.write_text(text)
    with pytest.raises(FormatError, match=f"name {path}#back for its back side"):
        patina.load_brdf(str(path))


@pytest.mark.parametrize("command", ["info", "validate", "convert"])
def test_names_that_are_not_utf8(tmp_path, merl_file, command, capsys):
    folder = os.fsencode(tmp_path) + b"/caf\xe9"
    os.mkdir(folder)
    files = [(os.path.join(ROOT, "materials", "red-plastic-iso.ptab"), b"/r\xff.ptab"), (merl_file, b"/m\xff.binary")]
    for source, name in files[: 1 if command == "validate" else 2]:  # validating a MERL file takes seconds
        path = os.fsdecode(folder + name)
        shutil.copy(source, path)
        args = [command, path] + ([os.fsdecode(folder + b"/out\xfe.ptab"), "--force"] if command == "convert" else [])
        status = main(args)
        assert status in ((0, 1) if command == "validate" else (0,)), capsys.readouterr().err  # 1: findings
        if command == "convert":
            written = patina.load_brdf(os.fsdecode(folder + b"/out\xfe.ptab"))
            assert np.array_equal(written.table.values, patina.load_brdf(path).table.values)
            assert not [n for n in os.listdir(folder) if n.startswith(b".")]  # no temporary file left
    assert "caf\\xe9" in capsys.readouterr().out  # the names shown with their bytes as \xNN


def test_an_engine_error_names_the_file_as_given(tmp_path):
    path = os.fsdecode(os.fsencode(tmp_path) + b"/bad\xff.ptab")
    with open(os.path.join(ROOT, "materials", "red-plastic-iso.ptab"), "rb") as f:
        open(path, "wb").write(f.read(100))
    with pytest.raises(FormatError) as e:
        patina.load_brdf(path)
    assert e.value.path.endswith("bad\\xff.ptab") and "truncated" in e.value.problem


@pytest.mark.parametrize(
    ("name", "content", "kind"),
    [
        ("settings.xml", b"<?xml version='1.0'?><config/>", None),
        ("notes.bin", bytes(1000), None),
        ("old.ptab", b"not a table", None),
        ("utia.bin", bytes(UTIA_BYTES), "utia"),
        ("w.xml", b"stray line\n<?xml version='1.0'?>\n<WindowElement/>", "window_xml"),
        ("long.xml", b"<?xml version='1.0'?>\n<!--" + b" " * 10000 + b"-->\n<WindowElement/>", "window_xml"),
        ("plain.csv", b"theta_i,theta_o,phi_d,value\n", "csv"),
    ],
)
def test_confirming_by_content(tmp_path, name, content, kind):
    path = tmp_path / name
    path.write_bytes(content)
    assert detect_format(str(path)) == (kind or detect_format(str(path)))  # unconfirmed: by extension
    if kind:
        assert detect_format(str(path), confirm=True) == kind
    else:
        with pytest.raises(FormatError, match=f"not a table: a {os.path.splitext(name)[1]} file without"):
            detect_format(str(path), confirm=True)
