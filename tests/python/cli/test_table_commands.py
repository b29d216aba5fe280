"""The patina command: output, JSON, and clear errors for bad input (exit 2, no traceback)."""

from __future__ import annotations

import argparse
import inspect
import json
import os
import subprocess
import sys

import numpy as np
import pytest

import patina
from patina import bundled
from patina.cli import build_parser, main
from patina.cli.common import HelpFormat
from repo_paths import ROOT

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
            assert main(["eval", bundled_ptab, "--wi", "30", "0", "--wo", "30", "180", "--json", "--simd", width]) == 0
            assert json.loads(capsys.readouterr().out)["values"] == doc["values"]


def test_simd_width_has_one_name(bundled_ptab, capsys):
    """`--simd` is the SIMD width on every command; `eval --width` (an image's width elsewhere) is gone."""
    assert main(["eval", bundled_ptab, "--wi", "30", "0", "--wo", "30", "180", "--width", "4"]) == 2
    assert "--width" in capsys.readouterr().err
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, command in sub.choices.items():
        options = {o: a for a in command._actions for o in a.option_strings}
        if "--simd" in options:
            assert tuple(options["--simd"].choices) == (1, 4, 8, 16), name
        if name in ("eval", "bench", "fit", "validate", "info"):
            assert "--width" not in options, name
    # the Python API says it the same way: render_scene(simd=), no width= beside an image's width
    parameters = inspect.signature(patina.render_scene).parameters
    assert "simd" in parameters and "width" not in parameters


@pytest.mark.parametrize(
    "value, width",
    [("1", 1), ("scalar", 1), ("4", 4), ("sse4", 4), ("8", 8), ("avx2", 8), ("16", 16), ("avx512", 16)],
)
def test_patina_simd_takes_the_numbers_simd_takes(value, width):
    if not patina._core.width_supported(width):
        pytest.skip(f"this CPU has no {width}-wide path")
    code = "from patina.native import _core; print(_core.default_width())"
    env = {**os.environ, "PATINA_SIMD": value}
    r = _run([sys.executable, "-c", code], env)
    assert r.returncode == 0 and r.stdout.strip() == str(width), r.stderr


def test_a_bad_patina_simd_is_one_line_naming_the_values(bundled_ptab):
    env = {**os.environ, "PATINA_SIMD": "32"}
    r = _run([*PATINA, "eval", bundled_ptab, "--wi", "0", "0", "--wo", "0", "0"], env)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert "PATINA_SIMD=32" in r.stderr and "1, 4, 8 or 16" in r.stderr


def _run(command: list[str], env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(command, check=False, capture_output=True, text=True, env=env or dict(os.environ))


def _help(*command: str) -> str:
    r = _run([*PATINA, *command, "--help"], {**os.environ, "COLUMNS": "200"})
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_every_option_has_help_and_shows_its_default():
    """Each option of each command says what it is, and one with a default shows it."""
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for name, command in sub.choices.items():
        assert command.formatter_class is HelpFormat, name
        for action in command._actions:
            if action.option_strings and not isinstance(action, argparse._SubParsersAction):
                assert action.help, f"patina {name} {action.option_strings[0]} has no help text"
    text = _help("eval")
    assert "incident direction" in text and "outgoing direction" in text
    text = _help("slices")
    assert "(default: [0, 20, 40, 60, 75])" in text and "incidence angles" in text
    assert "(default: 7)" in _help("bench")
    assert "(default: 5.0)" in _help("validate")


def test_output_into_a_closed_pipe_is_not_an_error(bundled_ptab):
    """`patina info FILE | head -1`: the reader leaves early; no "Broken pipe", no traceback."""
    for command in (["info", bundled_ptab], ["info", bundled_ptab, "--json"], ["--help"]):
        shell = " ".join(f"'{a}'" for a in [*PATINA, *command]) + " | head -1"
        r = _run(["bash", "-o", "pipefail", "-c", shell])
        assert r.stdout.count("\n") == 1, r.stdout
        assert r.stderr == "", r.stderr
        assert r.returncode in (0, 141), r.returncode  # 141: as a process killed by SIGPIPE


def test_quiet_leaves_only_errors(bundled_ptab, tmp_path):
    out = tmp_path / "b.json"
    r = _run([*PATINA, "bench", "--only", "math", "--quick", "--repeat", "1", "--json", str(out), "--quiet"])
    assert r.returncode == 0 and r.stdout == "" and r.stderr == "", (r.stdout, r.stderr)
    assert json.loads(out.read_text())["records"]
    r = _run([*PATINA, "bench", "--only", "nothing", "--quiet"])
    assert r.returncode == 2 and "(--only): invalid choice: 'nothing'" in r.stderr
    scene = os.path.join(ROOT, "materials", "scenes", "lambert-plane-point.json")
    tiny = ["--spp", "1", "--width", "16", "--height", "12", "--quiet"]
    r = _run([*PATINA, "render", scene, *tiny, "--out", str(tmp_path / "q.exr")])
    assert r.returncode == 0 and r.stdout == "" and r.stderr == "", (r.stdout, r.stderr)
    assert (tmp_path / "q.exr").exists()


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
    assert main(["eval", bundled_ptab, "--wi", "30", "--wo", "30", "0"]) == 2  # a missing angle
    assert main(["bench", "--only", "nothing"]) == 2
    assert main(["bench", "--only", "math", "--large"]) == 2  # --large sizes the cache group only
    assert "does not apply to group 'math'" in capsys.readouterr().err
    assert main(["bench", "--only", "cache", "--large", "--quick"]) == 2
    assert "does not apply to --quick" in capsys.readouterr().err


def test_bench_quick_writes_records(tmp_path, capsys):
    out = tmp_path / "b.json"
    assert main(["bench", "--only", "math", "--quick", "--repeat", "1", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    names = {r["name"] for r in doc["records"]}
    assert "math.acos.w4" in names
    for r in doc["records"]:
        assert set(r) == {"name", "candidate", "baseline", "ratio", "value", "unit"}
        assert r["ratio"] > 0 and r["value"] > 0


def test_bench_shows_progress_per_group(tmp_path):
    """A line per finished group (the whole run takes minutes), progress on stderr, the table on stdout."""
    r = _run([*PATINA, "bench", "--only", "brdf", "--quick", "--repeat", "1"])
    assert r.returncode == 0, r.stderr
    assert "bench: math:" in r.stderr and "bench: brdf:" in r.stderr and "records in" in r.stderr
    assert "2/2" in r.stderr  # the bar's done/total
    assert "bench:" not in r.stdout and r.stdout.startswith("name")
    assert "(1/2 groups done, about" in r.stderr and "(2/2 groups done)" in r.stderr


def test_bench_checks_its_output_and_inputs_before_timing(tmp_path):
    (tmp_path / "a-file").write_text("")
    out = tmp_path / "a-file" / "b.json"
    r = _run([*PATINA, "bench", "--only", "math", "--quick", "--repeat", "1", "--json", str(out)])
    assert r.returncode == 2 and str(out) in r.stderr and "Traceback" not in r.stderr
    assert "bench: math:" not in r.stderr  # refused before the first group
    # a folder that does not exist yet is made
    out = tmp_path / "new" / "b.json"
    assert _run([*PATINA, "bench", "--only", "math", "--quick", "--repeat", "1", "--json", str(out)]).returncode == 0
    assert json.loads(out.read_text())["records"]


def test_bench_needs_the_checkout_for_scene_groups_and_says_so_first(tmp_path, monkeypatch, capsys):
    """Outside a checkout (no materials/ anywhere) the render and lights groups are refused up front."""
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(bundled, "_SOURCE_TREE", str(tmp_path))
    assert main(["bench", "--only", "lights", "--quick", "--repeat", "1"]) == 2
    err = capsys.readouterr().err
    assert "materials/scenes not found" in err and "bench: lights:" not in err
