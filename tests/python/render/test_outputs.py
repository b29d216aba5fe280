"""patina.render.outputs through `patina render`: an output that cannot be written whole is
not written, is named in one line, exit 2; nothing (no truncated image, no temporary) is left."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from full_disk import files_in, full_folder
from repo_paths import ROOT

BALL = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")


@pytest.mark.parametrize("name", ["ball.png", "ball.jpg", "ball.exr"])
def test_render_onto_a_full_disk(tmp_path, name):
    """Before: the PNG was left truncated with "wrote" and exit 0; libjpeg ended the process
    (exit 1, no Patina line) leaving its temporary; the EXR's message did not name it."""
    with full_folder(str(tmp_path)) as full:
        out = os.path.join(full, name)
        cmd = [sys.executable, "-m", "patina.cli", "render", BALL, "--spp", "1", "--width", "96", "--out", out]
        done = subprocess.run([*cmd, "--threads", "1"], check=False, capture_output=True, text=True, timeout=120)
        assert done.returncode == 2, done.stderr
        assert "wrote" not in done.stdout
        lines = [line for line in done.stderr.splitlines() if line.startswith("patina")]
        assert len(lines) == 1 and "Traceback" not in done.stderr, done.stderr
        assert lines[0] == f"patina: error: {out}: cannot write: No space left on device"
        assert files_in(full) == []


@pytest.mark.parametrize("quiet", [[], ["--quiet"]])
def test_an_output_name_that_is_not_utf8(tmp_path, quiet):
    """Before, with --quiet: "surrogates not allowed" and exit 2 after the render."""
    out = os.path.join(tmp_path, os.fsdecode(b"ball \xff.png"))
    cmd = [sys.executable, "-m", "patina.cli", "render", BALL, "--spp", "1", "--width", "32", "--out", out, *quiet]
    done = subprocess.run(cmd, check=False, capture_output=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert os.listdir(os.fsencode(tmp_path)) == [b"ball \xff.png"]
