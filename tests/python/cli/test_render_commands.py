"""`patina render` and `patina preview`: outputs, metadata, and bad input (exit 2, one line
naming the file, the key and the problem, nothing written)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys

import numpy as np
import pytest

from patina.cli import main
from patina.render.images import read_exr_layers
from repo_paths import ROOT

TABLE = os.path.join(ROOT, "materials", "red-plastic-iso.ptab")
SMALL = ["--spp", "2", "--width", "32", "--height", "24", "--quiet"]


def test_render_writes_an_exr_with_aovs_and_metadata_and_a_png(tmp_path, capsys):
    out = tmp_path / "out" / "ball.exr"
    scene = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")
    assert main(["render", scene, "--out", str(out), *SMALL]) == 0
    assert "complete" in capsys.readouterr().out
    layers, meta = read_exr_layers(str(out))
    assert set(layers) >= {"beauty", "albedo", "normal", "depth", "illuminance"}
    assert layers["beauty"].shape == (24, 32, 3)
    assert np.isfinite(layers["beauty"]).all() and layers["beauty"].max() > 0
    assert int(meta["patina:spp"]) == 2 and int(meta["patina:complete"]) == 1
    assert json.loads(str(meta["patina:scene"]))["camera"]["width"] == 32
    assert (tmp_path / "out" / "ball.png").stat().st_size > 0
    assert sorted(os.listdir(tmp_path / "out")) == ["ball.exr", "ball.png"]  # no temporary files left


@pytest.mark.parametrize("shape", ["sphere", "panel", "ball"])
def test_preview_renders_a_table_with_and_without_a_coat(tmp_path, shape):
    out = tmp_path / "p.exr"
    assert main(["preview", TABLE, "--shape", shape, "--out", str(out), "--png", "none", *SMALL]) == 0
    assert out.exists() and not (tmp_path / "p.png").exists()
    assert main(["preview", TABLE, "--shape", shape, "--coat", "--out", str(out), *SMALL]) == 0


def test_preview_renders_a_fit_json(tmp_path):
    fit = tmp_path / "fit.json"
    params = {"rho_r": 0.5, "rho_g": 0.1, "rho_b": 0.05, "alpha": 0.2, "f0_r": 0.04, "f0_g": 0.04, "f0_b": 0.04}
    fit.write_text(json.dumps({"model": "ggx+lambert", "parameters": params}))
    assert main(["preview", str(fit), "--shape", "sphere", "--out", str(tmp_path / "f.exr"), *SMALL]) == 0


def write_scene(tmp_path, obj) -> str:
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(obj) if not isinstance(obj, str) else obj)
    return str(path)


GOOD = {
    "version": 1,
    "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 16, "height": 12},
    "materials": {"m": {"type": "lambert", "albedo": 0.5}},
    "shapes": [{"type": "sphere", "material": "m"}],
    "environment": {"type": "constant", "radiance": 1},
}


@pytest.mark.parametrize(
    ("change", "where"),
    [
        ({"camera": {**GOOD["camera"], "fvo": 30}}, "camera.fvo"),
        ({"materials": {"m": {"type": "lambert", "albedo": -1}}}, "materials.m.albedo"),
        ({"shapes": [{"type": "mesh", "material": "m", "file": "missing.obj"}]}, "shapes[0].file"),
        ({"shapes": [{"type": "sphere", "material": "nope"}]}, "shapes[0].material"),
        ({"environment": {"type": "map", "file": "missing.exr"}}, "environment.file"),
    ],
)
def test_bad_scenes_exit_2_naming_file_and_key_and_write_nothing(tmp_path, capsys, change, where):
    scene = write_scene(tmp_path, {**GOOD, **change})
    out = tmp_path / "never.exr"
    assert main(["render", scene, "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert scene in err and where in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_unreadable_environment_and_mesh_files_are_clear_errors(tmp_path, capsys):
    (tmp_path / "env.exr").write_bytes(b"not an exr at all")
    (tmp_path / "bad.obj").write_text("v 0 0 0\nf 1 2 3\n")
    for change in (
        {"environment": {"type": "map", "file": "env.exr"}},
        {"shapes": [{"type": "mesh", "material": "m", "file": "bad.obj"}]},
    ):
        scene = write_scene(tmp_path, {**GOOD, **change})
        assert main(["render", scene, "--out", str(tmp_path / "x.exr"), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert "Traceback" not in err and ("env.exr" in err or "bad.obj" in err)
    assert not (tmp_path / "x.exr").exists()


def test_bad_json_and_bad_options(tmp_path, capsys):
    scene = write_scene(tmp_path, '{"version": 1, "camera": {')
    assert main(["render", scene, "--quiet"]) == 2
    assert "line 1" in capsys.readouterr().err
    good = write_scene(tmp_path, GOOD)
    assert main(["render", good, "--spp", "0", "--quiet"]) == 2
    assert "--spp" in capsys.readouterr().err


def test_ctrl_c_writes_a_valid_partial_image_and_exits_130(tmp_path):
    scene = write_scene(tmp_path, {**GOOD, "camera": {**GOOD["camera"], "width": 64, "height": 48}})
    out = tmp_path / "partial.exr"
    cmd = [sys.executable, "-m", "patina.cli", "render", scene, "--out", str(out), "--spp", "1000000", "--quiet"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None and proc.stdout.readline().startswith("rendering")
        import time

        time.sleep(1.0)  # some passes finish
        proc.send_signal(signal.SIGINT)
        stdout, stderr = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr and "PARTIAL" in stdout
    layers, meta = read_exr_layers(str(out))
    assert int(meta["patina:complete"]) == 0
    assert 0 < int(meta["patina:samples_min"]) < 1000000
    assert np.isfinite(layers["beauty"]).all() and layers["beauty"].mean() > 0.1
    assert sorted(os.listdir(tmp_path)) == ["partial.exr", "partial.png", "scene.json"]
