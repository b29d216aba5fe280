"""The patina command: output, JSON, and clear errors for bad input (exit 2, no traceback)."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import patina
from patina.cli import main

PATINA = [sys.executable, "-m", "patina.cli"]


def test_info_text_and_json(bundled_ptab, capsys):
    assert main(["info", bundled_ptab]) == 0
    out = capsys.readouterr().out
    assert "isotropic" in out and "phi_d" in out
    assert main(["info", bundled_ptab, "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["channels"] == 3 and info["grid_points"] == 30 * 30 * 60


def test_eval_json_holds_channel_values(bundled_ptab, capsys):
    assert main(["eval", bundled_ptab, "--wi", "30", "0", "--wo", "30", "180", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    want = patina.load_brdf(bundled_ptab).eval_angles(*np.radians([30, 0, 30, 180]))
    np.testing.assert_allclose(doc["values"], want, rtol=1e-6)
    assert doc["channels"] == ["R", "G", "B"]
    for width in ("1", "4", "8"):
        if patina._core.width_supported(int(width)):
            assert main(["eval", bundled_ptab, "--wi", "30", "0", "--wo", "30", "180", "--json", "--width", width]) == 0
            assert json.loads(capsys.readouterr().out)["values"] == doc["values"]


def test_convert_astm_to_ptab(bundled_astm, tmp_path, capsys):
    out = tmp_path / "c.ptab"
    assert main(["convert", bundled_astm, str(out)]) == 0
    assert patina.load_brdf(out).info()["grid_points"] == 10 * 10 * 19


def test_slices_png(bundled_ptab, tmp_path):
    out = tmp_path / "s.png"
    assert main(["slices", bundled_ptab, "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "content, message",
    [(b"", "unrecognised"), (b"PTAB\r\n\x1a\n\x01\x00", "truncated"), (b"VARS theta_i\n1 2\n", "line")],
)
def test_bad_files_exit_2_with_a_clear_message(tmp_path, content, message):
    path = tmp_path / ("bad.ptab" if content.startswith(b"PTAB") else "bad.astm" if b"VARS" in content else "bad.dat")
    if content == b"":
        path = tmp_path / "empty.xyz"
    path.write_bytes(content)
    r = subprocess.run([*PATINA, "info", str(path)], check=False, capture_output=True, text=True, env=dict(os.environ))
    assert r.returncode == 2
    assert str(path) in r.stderr and message in r.stderr
    assert "Traceback" not in r.stderr


def test_bad_options(bundled_ptab, capsys):
    assert main(["eval", bundled_ptab, "--wi", "95", "0", "--wo", "30", "0"]) == 2
    assert "outside [0, 90]" in capsys.readouterr().err
    assert main(["convert", bundled_ptab, "out.exr"]) == 2
    assert ".ptab" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:  # argparse: a missing angle
        main(["eval", bundled_ptab, "--wi", "30", "--wo", "30", "0"])
    assert e.value.code == 2
    assert main(["bench", "--only", "nothing"]) == 2


def test_bench_quick_writes_records(tmp_path, capsys):
    out = tmp_path / "b.json"
    assert main(["bench", "--only", "math", "--quick", "--repeat", "1", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    names = {r["name"] for r in doc["records"]}
    assert "math.acos.w4" in names
    for r in doc["records"]:
        assert set(r) == {"name", "candidate", "baseline", "ratio", "value", "unit"}
        assert r["ratio"] > 0 and r["value"] > 0
