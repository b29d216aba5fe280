"""`patina render` and `patina preview`: outputs, metadata, and bad input (exit 2, one line
naming the file, the key and the problem, nothing written)."""

from __future__ import annotations

import json
import os
import signal
import sys

import numpy as np
import pytest

from interrupts import start_interruptible
from patina.cli import main
from patina.render.images import read_exr_layers
from repo_paths import ROOT
from rgl_tables import write_glossy_rgl

TABLE = os.path.join(ROOT, "materials", "red-plastic-iso.ptab")
SMALL = ["--spp", "2", "--width", "32", "--height", "24", "--quiet"]
LOUD = SMALL[:-1]  # --quiet silences stdout too


def test_render_writes_an_exr_with_aovs_and_metadata_and_a_png(tmp_path, capsys):
    out = tmp_path / "out" / "ball.exr"
    scene = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")
    assert main(["render", scene, "--out", str(out), *LOUD]) == 0
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
    assert main(["preview", TABLE, "--shape", shape, "--coat", "--out", str(out), "--force", *SMALL]) == 0


def test_preview_renders_an_rgl_file_as_the_native_rgl_material(tmp_path):
    rgl = write_glossy_rgl(str(tmp_path / "glossy.bsdf"))
    out = tmp_path / "r.exr"
    assert main(["preview", rgl, "--shape", "sphere", "--out", str(out), "--png", "none", *SMALL]) == 0
    layers, meta = read_exr_layers(str(out))
    assert np.isfinite(layers["beauty"]).all() and layers["beauty"].max() > 0
    material = json.loads(str(meta["patina:scene"]))["materials"]["material"]
    assert (material["type"], material["sampling"]) == ("rgl", "file")


def test_preview_renders_a_fit_json(tmp_path):
    fit = tmp_path / "fit.json"
    params = {"rho_r": 0.5, "rho_g": 0.1, "rho_b": 0.05, "alpha": 0.2, "f0_r": 0.04, "f0_g": 0.04, "f0_b": 0.04}
    fit.write_text(json.dumps({"model": "ggx+lambert", "parameters": params}))
    assert main(["preview", str(fit), "--shape", "sphere", "--out", str(tmp_path / "f.exr"), *SMALL]) == 0


def test_preview_renders_the_side_of_a_bsdf_xml_named_after_it(tmp_path, capsys):
    shade = os.path.join(ROOT, "materials", "radiance", "klems_aniso_high.xml")
    means = []
    for side in ("", "#back"):
        out = tmp_path / f"shade{side.strip('#')}.exr"
        assert main(["preview", shade + side, "--out", str(out), "--png", "none", *SMALL]) == 0
        means.append(read_exr_layers(str(out))[0]["beauty"].mean())
    assert means[0] != means[1]  # the back side reached the renderer
    assert main(["preview", shade + "#top", "--out", str(tmp_path / "t.exr"), *SMALL]) == 2
    err = capsys.readouterr().err
    assert "expected #front or #back" in err and len(err.strip().splitlines()) == 1


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
        (
            {"shapes": [{"type": "sphere", "material": "m", "analytic": True, "transform": {"scale": [1, 2, 1]}}]},
            "shapes[0].analytic",
        ),
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


@pytest.mark.parametrize("integrator", ["cache", "cache-guided"])
def test_the_cache_integrators_render_and_record_their_statistics(tmp_path, capsys, integrator):
    out = tmp_path / "c.exr"
    box = os.path.join(ROOT, "materials", "scenes", "area-box.json")
    options = ["--spp", "1", "--width", "24", "--height", "24", "--cache-resolution", "8"]
    options += ["--cache-train-passes", "0"]  # cache-guided: the cache points guide (the trained guide has none)
    assert main(["render", box, "--integrator", integrator, "--out", str(out), "--png", "none", *options]) == 0
    assert "radiance cache:" in capsys.readouterr().out
    layers, meta = read_exr_layers(str(out))
    assert meta["patina:integrator"] == integrator
    assert int(meta["patina:cache_points"]) > 0 and int(meta["patina:cache_queries"]) > 0
    assert np.isfinite(layers["beauty"]).all() and layers["beauty"].mean() > 0


@pytest.mark.parametrize(
    ("options", "named"),
    [(["--integrator", "photon"], "--integrator"), (["--cache-resolution", "4"], "--cache-resolution"),
     (["--cache-error", "9"], "--cache-error"), (["--cache-guide", "1"], "--cache-guide"),
     (["--cache-train-passes", "9"], "--cache-train-passes"), (["--cache-train-spp", "0"], "--cache-train-spp"),
     (["--cache-train-guide", "1"], "--cache-train-guide"), (["--cache-train-bounces", "0"], "--cache-train-bounces")],
)  # fmt: skip
def test_bad_cache_options_exit_2_naming_the_option(tmp_path, capsys, options, named):
    box = os.path.join(ROOT, "materials", "scenes", "area-box.json")
    assert main(["render", box, "--out", str(tmp_path / "x.exr"), *options, *SMALL]) == 2
    err = capsys.readouterr().err
    assert named in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.exr").exists()


def test_ctrl_c_writes_a_valid_partial_image_and_exits_130(tmp_path):
    scene = write_scene(tmp_path, {**GOOD, "camera": {**GOOD["camera"], "width": 64, "height": 48}})
    out = tmp_path / "partial.exr"
    cmd = [sys.executable, "-m", "patina.cli", "render", scene, "--out", str(out), "--spp", "1000000"]
    proc = start_interruptible(cmd)
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


BALL = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")


@pytest.mark.parametrize("name", ["x.png", "x.jpg", "x.JPEG"])
def test_an_image_out_writes_only_the_tone_mapped_image(tmp_path, capsys, name):
    # it used to render, then fail: "png does not support 11-channel images"
    assert main(["render", BALL, "--out", str(tmp_path / name), *LOUD]) == 0
    assert os.listdir(tmp_path) == [name]
    import OpenImageIO as oiio

    image = oiio.ImageBuf(str(tmp_path / name))
    assert (image.spec().width, image.spec().height, image.spec().nchannels) == (32, 24, 3)
    assert f"wrote {tmp_path / name}" in capsys.readouterr().out


def test_an_image_out_with_exr_writes_both(tmp_path):
    assert main(["render", BALL, "--out", str(tmp_path / "x.png"), "--exr", str(tmp_path / "f.exr"), *SMALL]) == 0
    assert sorted(os.listdir(tmp_path)) == ["f.exr", "x.png"]
    assert read_exr_layers(str(tmp_path / "f.exr"))[0]["beauty"].shape == (24, 32, 3)


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--out", "x.tif"], "--out"),
        (["--out", "x.png", "--png", "y.png"], "--png"),
        (["--out", "x.exr", "--png", "y.exr"], "--png"),
        (["--out", "x.exr", "--exr", "y.exr"], "--exr"),
        (["--out", "x.png", "--exr", "y.png"], "--exr"),
    ],
)
def test_bad_output_options_exit_2_before_rendering(tmp_path, monkeypatch, capsys, options, named):
    monkeypatch.chdir(tmp_path)
    assert main(["render", BALL, *options, *SMALL]) == 2
    captured = capsys.readouterr()
    assert named in captured.err and len(captured.err.strip().splitlines()) == 1
    assert "rendering" not in captured.out and os.listdir(tmp_path) == []


@pytest.mark.parametrize("existing", ["x.exr", "x.png"])
def test_an_existing_output_is_refused_without_force_before_rendering(tmp_path, capsys, existing):
    (tmp_path / existing).write_bytes(b"keep me")
    out = str(tmp_path / "x.exr")
    assert main(["render", BALL, "--out", out, *SMALL]) == 2
    captured = capsys.readouterr()
    assert captured.err.strip() == f"patina: error: {tmp_path / existing}: exists; pass --force to overwrite it"
    assert "rendering" not in captured.out
    assert (tmp_path / existing).read_bytes() == b"keep me" and os.listdir(tmp_path) == [existing]
    assert main(["render", BALL, "--out", out, "--force", *SMALL]) == 0
    assert (tmp_path / existing).read_bytes() != b"keep me"


def test_preview_also_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "p.png"
    assert main(["preview", TABLE, "--out", str(out), *SMALL]) == 0
    assert main(["preview", TABLE, "--out", str(out), *SMALL]) == 2
    assert "exists; pass --force" in capsys.readouterr().err


def test_an_unwritable_output_is_reported_before_rendering(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    assert main(["render", BALL, "--out", str(tmp_path / "file" / "x.exr"), *SMALL]) == 2
    captured = capsys.readouterr()
    assert "rendering" not in captured.out and str(tmp_path / "file") in captured.err


@pytest.mark.parametrize(("options", "size"), [(["--width", "40"], (40, 30)), (["--height", "60"], (80, 60))])
def test_a_lone_width_or_height_keeps_the_scenes_aspect(tmp_path, options, size):
    # preview-ball.json is 4:3; --width alone used to keep the file's height (a crop)
    out = tmp_path / "x.exr"
    assert main(["render", BALL, "--out", str(out), "--spp", "1", "--quiet", *options]) == 0
    assert read_exr_layers(str(out))[0]["beauty"].shape[:2] == (size[1], size[0])


def test_preview_lists_its_shapes_for_an_unknown_one(tmp_path, capsys):
    assert main(["preview", TABLE, "--shape", "cube", "--out", str(tmp_path / "p.exr"), *SMALL]) == 2
    err = capsys.readouterr().err
    assert "--shape" in err and "'cube'" in err and "ball, sphere, panel" in err and "mesh file" in err
    assert len(err.strip().splitlines()) == 1 and os.listdir(tmp_path) == []


def test_preview_exposure_is_auto_under_a_map_far_from_the_studio(tmp_path, capsys):
    from patina.cli.render import preview_exposure

    sky = os.path.join(ROOT, "materials", "env", "sky.exr")
    assert preview_exposure(None) == "0"
    assert preview_exposure(os.path.join(ROOT, "materials", "env", "studio.exr")) == "0"
    assert preview_exposure(sky) == "auto"  # ~5 stops brighter than the studio
    out = tmp_path / "p.exr"
    assert main(["preview", TABLE, "--env", sky, "--out", str(out), *LOUD]) == 0
    assert "stops" in capsys.readouterr().out
    import OpenImageIO as oiio

    png = oiio.ImageBuf(str(tmp_path / "p.png")).get_pixels(oiio.FLOAT)
    assert png.mean() < 0.9  # it used to be an all-white frame
    assert main(["preview", TABLE, "--env", sky, "--out", str(out), "--force", "--exposure", "0", *SMALL]) == 0
    assert oiio.ImageBuf(str(tmp_path / "p.png")).get_pixels(oiio.FLOAT).mean() > png.mean()


def test_render_help_shows_defaults_and_a_text_for_every_option(capsys):
    from patina.cli import build_parser

    parser = build_parser()
    for command in ("render", "preview", "illuminance"):
        sub = parser._subparsers._group_actions[0].choices[command]  # type: ignore[union-attr]
        for action in sub._actions:
            assert action.help, f"{command} {action.option_strings} has no help"
        text = sub.format_help()
        assert "default" in text
    text = " ".join(parser._subparsers._group_actions[0].choices["render"].format_help().split())  # type: ignore[union-attr]
    assert "(default: filmic)" in text and "(default: render.exr)" in text


def test_progress_is_shown_when_not_a_terminal_and_not_with_quiet(tmp_path, capsys):
    opts = ["--spp", "2", "--width", "32"]
    assert main(["render", BALL, "--out", str(tmp_path / "a.png"), *opts]) == 0
    err = capsys.readouterr().err
    assert "rendering" in err and "2/2" in err.replace("2.0/2", "2/2") and "Mrays/s" in err
    # in a log each update is a line of its own: no carriage returns that a log never moves back on
    assert "\r" not in err and err.endswith("\n")
    assert main(["render", BALL, "--out", str(tmp_path / "b.png"), *opts, "--quiet"]) == 0
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize(
    ("material", "content", "where"),
    [
        ("out.png", b"\x89PNG\r\n\x1a\n", "out.png (MATERIAL): 'out.png' is not one of the file kinds"),
        ("broken.json", b'{"model": 3}', "broken.json (MATERIAL, model): "),
        ("bad.astm", b"x", "bad.astm (MATERIAL, VARS): "),
    ],
)
@pytest.mark.parametrize("coat", [[], ["--coat"]])
def test_preview_names_the_material_as_given_not_a_made_up_scene(
    material, content, where, coat, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    (tmp_path / material).write_bytes(content)
    assert main(["preview", material, *coat, "--out", "p.exr", *SMALL]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [err.strip()] and err.startswith(f"patina: error: {where}"), err
    assert "(preview)" not in err and str(tmp_path) not in err
    assert sorted(os.listdir(tmp_path)) == [material]


@pytest.mark.parametrize(
    "option", [["--height", "1e300"], ["--grid", "0,0,1e300,1,2,2"], ["--grid", "-3.5,-15,3.5,15,8,1_0"]]
)
def test_illuminance_coordinates_are_range_checked_before_the_scene_is_read(option, capsys):
    scene = os.path.join(ROOT, "materials", "scenes", "street-luminaire.json")
    grid = [] if option[0] == "--grid" else ["--grid", "0,0,1,1,2,2"]
    assert main(["illuminance", scene, *grid, *option]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"patina illuminance: error: command line ({option[0]}): ") and "\n" not in err, err
    assert "from -100000 to 100000" in err or "from 1 to 4096" in err
