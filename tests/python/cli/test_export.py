"""`patina export`: every target written with its sidecar, and bad input refused in one line
with exit 2 and nothing written."""

from __future__ import annotations

import json
import os

import pytest

import patina.export
from export_helpers import GGX_FIT, WARD_FIT, write_json
from patina.cli import main

SUFFIX = {"mitsuba": "xml", "pbrt": "pbrt", "materialx": "mtlx", "gltf": "glb", "usd": "usda", "blender": "py"}


@pytest.mark.parametrize("target", sorted(SUFFIX))
def test_each_target_writes_its_file_and_sidecar(tmp_path, capsys, target):
    fit = write_json(tmp_path / "plastic.json", GGX_FIT)
    out = tmp_path / f"plastic.{SUFFIX[target]}"
    assert main(["export", fit, "--to", target, "--out", str(out)]) == 0
    assert out.stat().st_size > 0
    sidecar = json.loads((tmp_path / f"plastic.{SUFFIX[target]}.export.json").read_text())
    assert sidecar["target"] == target and sidecar["refitted"] is False
    assert sidecar["error_against_source"]["relative_error_median"] == 0
    if target == "mitsuba" and sidecar["target_error_against_source"] is not None:  # Mitsuba's own evaluation
        assert sidecar["target_error_against_source"]["relative_error_median"] < 0.01
    assert "exact" in capsys.readouterr().out


def test_ward_fit_is_refitted_and_its_error_printed(tmp_path, capsys):
    fit = write_json(tmp_path / "ward.json", WARD_FIT)
    out = tmp_path / "ward.mtlx"
    assert main(["export", fit, "--to", "materialx", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "refitted" in printed and "CIEDE2000 mean" in printed
    sidecar = json.loads((tmp_path / "ward.mtlx.export.json").read_text())
    assert sidecar["refitted"] and sidecar["material"]["lobes"][0]["distribution"] == "ggx"
    assert sidecar["error_against_source"]["ciede2000_mean"] > 0


def _one_line_error(capsys) -> str:
    """The one error line (progress lines of a refit may come before it on stderr)."""
    err = capsys.readouterr().err
    errors = [line for line in err.splitlines() if line.startswith("patina")]
    assert len(errors) == 1 and "Traceback" not in err, err
    return errors[0]


def test_existing_output_is_refused_without_force(tmp_path, capsys):
    fit = write_json(tmp_path / "p.json", GGX_FIT)
    out = tmp_path / "p.xml"
    out.write_text("keep")
    assert main(["export", fit, "--to", "mitsuba", "--out", str(out)]) == 2
    assert "--force" in _one_line_error(capsys) and out.read_text() == "keep"
    assert main(["export", fit, "--to", "mitsuba", "--out", str(out), "--force"]) == 0
    assert out.read_text().startswith("<!--")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--to", "renderman", "--out", "x.xml"], "(--to): invalid choice: 'renderman'"),
        (["--to", "mitsuba", "--out", "x.glb"], "--out x.glb: a mitsuba file ends with .xml"),
        (["--to", "gltf", "--out", "x.glb", "--standard-surface"], "--standard-surface"),
    ],
)
def test_bad_options_end_in_one_line(tmp_path, capsys, monkeypatch, args, message):
    fit = write_json(tmp_path / "p.json", GGX_FIT)
    monkeypatch.chdir(tmp_path)
    assert main(["export", fit, *args]) == 2
    assert message in _one_line_error(capsys)
    assert sorted(os.listdir(tmp_path)) == ["p.json"]


def test_unreadable_material_names_the_file(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text('{"model": "ggx+lambert", "parameters": {"alpha": "rough"}}')
    assert main(["export", str(bad), "--to", "usd", "--out", str(tmp_path / "o.usda")]) == 2
    assert "bad.json (parameters.alpha): must be a number" in _one_line_error(capsys)
    assert sorted(os.listdir(tmp_path)) == ["bad.json"]


def test_failed_refit_is_refused_and_nothing_is_written(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(patina.export, "MAX_REFIT_DE", 0.0)  # no refit is good enough
    fit = write_json(tmp_path / "ward.json", WARD_FIT)
    assert main(["export", fit, "--to", "gltf", "--out", str(tmp_path / "w.glb")]) == 2
    assert "gltf cannot hold ward+lambert" in _one_line_error(capsys)
    assert sorted(os.listdir(tmp_path)) == ["ward.json"]


def test_table_option_measures_the_export_against_the_measurements(tmp_path, capsys, bundled_ptab):
    fit = write_json(tmp_path / "p.json", GGX_FIT)
    out = tmp_path / "p.pbrt"
    assert main(["export", fit, "--to", "pbrt", "--out", str(out), "--table", bundled_ptab]) == 0
    sidecar = json.loads((tmp_path / "p.pbrt.export.json").read_text())
    assert sidecar["measured_against"] == bundled_ptab
    assert sidecar["error_against_source"]["relative_error_median"] > 0  # the fit's own error against the table
    assert bundled_ptab in capsys.readouterr().out
