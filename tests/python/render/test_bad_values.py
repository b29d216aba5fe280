"""Values that pass the schema but would break the arithmetic (issue 10, defects 10-13): each
is refused before any work with one line naming the file and the key, or handled; outputs
never fail at the last step because a value does not fit its type."""

from __future__ import annotations

import json
import os
import warnings

import numpy as np
import OpenImageIO as oiio
import pytest

from patina import atomic
from patina.cli import main
from patina.errors import FormatError
from patina.fitting.fit_file import read_fit
from patina.geometry import shapes
from patina.render import images, prepare
from patina.render.images import read_exr_layers, write_exr
from patina.render.outputs import metadata
from patina.render.prepare import PreparedScene, check_render_memory
from patina.render.run import RenderResult, render
from patina.scene.reading import load_scene, parse_scene
from patina.table import load_brdf
from patina.table.brdf import Brdf
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData
from repo_paths import ROOT

TABLE = os.path.join(ROOT, "materials", "red-plastic-iso.ptab")


def scene_dict(**changes: object) -> dict:
    s: dict = {
        "version": 1,
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 12, "height": 8},
        "render": {"spp": 1},
        "materials": {"grey": {"type": "lambert", "albedo": 0.5}},
        "shapes": [{"type": "sphere", "material": "grey"}],
        "environment": {"type": "constant", "radiance": 1},
    }
    s.update(changes)
    return s


def write_scene(tmp_path, obj: dict, name: str = "scene.json") -> str:
    path = tmp_path / name
    path.write_text(json.dumps(obj))
    return str(path)


# ---------------------------------------------------------------- 10: metadata and seeds


def test_metadata_beyond_32_bits_is_written_as_text_not_refused(tmp_path):
    path = tmp_path / "m.exr"
    write_exr(path, {"beauty": np.zeros((2, 2, 3))}, {"a:rays": 2**40, "a:seed": 3_000_000_000, "a:small": 7})
    _, meta = read_exr_layers(str(path))
    assert meta["a:rays"] == str(2**40) and meta["a:seed"] == "3000000000" and meta["a:small"] == 7


def test_render_metadata_has_rays_and_seed_as_decimal_text(tmp_path):
    scene = parse_scene(scene_dict(render={"spp": 1, "seed": 2**63 - 1}), tmp_path / "s.json")
    image = np.zeros((1, 1, 3), np.float32)
    result = RenderResult(
        rgb=image,
        albedo=image,
        normal=image,
        depth=np.ones((1, 1), np.float32),
        illuminance=np.zeros((1, 1), np.float32),
        samples=np.ones((1, 1)),
        spp=1,
        seconds=1.0,
        rays=3 * 2**31,
        complete=True,
        simd_width=4,
        threads=2,
    )
    meta = metadata(scene, result)
    assert meta["patina:seed"] == str(2**63 - 1) and meta["patina:rays"] == str(3 * 2**31)
    write_exr(tmp_path / "r.exr", {"beauty": np.zeros((1, 1, 3))}, meta)  # fits every attribute type


def test_every_documented_seed_renders_and_high_bits_change_the_image(tmp_path):
    def image(seed: int) -> np.ndarray:
        obj = scene_dict(
            render={"spp": 2, "seed": seed}, lights=[{"type": "point", "position": [2, 2, 2], "intensity": 5}]
        )
        return render(parse_scene(obj, tmp_path / "s.json")).rgb

    low, high = image(5), image(2**32 + 5)
    assert np.isfinite(image(2**63 - 1)).all()
    assert not np.array_equal(low, high)  # the bits above 32 are not dropped


# ---------------------------------------------------------------- 11: ranges before rendering

BAD_SCENES = [
    (
        "sun of 1e-300 degrees",
        {"lights": [{"type": "sun", "direction": [0, 1, 0], "angular_diameter": 1e-300, "irradiance": 1}]},
        "lights[0].angular_diameter",
    ),
    (
        "point light 1e38",
        {"lights": [{"type": "point", "position": [0, 3, 3], "intensity": 1e38}]},
        "lights[0].intensity",
    ),
    (
        "point light 1e38 cd",
        {"lights": [{"type": "point", "position": [0, 3, 3], "intensity_cd": 1e38}]},
        "lights[0].intensity_cd",
    ),
    (
        "quad radiance 1e300",
        {"lights": [{"type": "quad", "center": [0, 3, 0], "u": [1, 0, 0], "v": [0, 0, 1], "radiance": 1e300}]},
        "lights[0].radiance",
    ),
    (
        "disk luminance 1e30",
        {"lights": [{"type": "disk", "center": [0, 3, 0], "normal": [0, -1, 0], "radius": 1, "luminance": 1e30}]},
        "lights[0].luminance",
    ),
    ("sky 1e20", {"environment": {"type": "constant", "radiance": 1e20}}, "environment.radiance"),
    (
        "sphere radius 1e-300",
        {"shapes": [{"type": "sphere", "material": "grey", "radius": 1e-300}]},
        "shapes[0].radius",
    ),
    (
        "scale 1e-100",
        {"shapes": [{"type": "sphere", "material": "grey", "transform": {"scale": 1e-100}}]},
        "shapes[0].transform.scale",
    ),
    (
        "position 1e30",
        {"lights": [{"type": "point", "position": [1e30, 0, 0], "intensity": 1}]},
        "lights[0].position[0]",
    ),
    ("eta 1e30", {"materials": {"grey": {"type": "dielectric", "eta": 1e30}}}, "materials.grey.eta"),
    ("tint 1e30", {"materials": {"grey": {"type": "conductor", "metal": "Au", "tint": 1e30}}}, "materials.grey.tint"),
    (
        "scale x tint",
        {"materials": {"grey": {"type": "table", "file": TABLE, "scale": 1e4, "tint": 1e4}}},
        "materials.grey.scale",
    ),
    (
        "sun too bright for its size",
        {"lights": [{"type": "sun", "direction": [0, 1, 0], "angular_diameter": 0.001, "irradiance": 1e12}]},
        "lights[0]",
    ),
]


@pytest.mark.parametrize(("case", "changes", "key"), BAD_SCENES, ids=[c[0] for c in BAD_SCENES])
def test_values_that_would_overflow_float32_are_refused_naming_the_file_and_key(tmp_path, case, changes, key):
    path = write_scene(tmp_path, scene_dict(**changes))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no numpy RuntimeWarning on the way
        with pytest.raises(FormatError) as e:
            PreparedScene(load_scene(path))
    assert e.value.path == path and e.value.where == key, str(e.value)


def test_the_cli_refuses_them_with_exit_2_and_one_line(tmp_path, capsys):
    path = write_scene(tmp_path, scene_dict(lights=[{"type": "point", "position": [0, 3, 3], "intensity": 1e38}]))
    assert main(["render", path, "--out", str(tmp_path / "o.exr"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "lights[0].intensity" in err[0] and "32-bit" in err[0]
    assert not (tmp_path / "o.exr").exists()


def test_a_table_of_huge_finite_values_is_refused_before_rendering(tmp_path):
    b = load_brdf(TABLE)
    data = TableData(b.parametrization, b.axes, np.full_like(b.values, 3e38), b.channel_kind, b.wavelengths)
    huge = tmp_path / "huge.ptab"
    Brdf(table_from_data(data)).save(huge)
    obj = scene_dict(materials={"grey": {"type": "table", "file": str(huge)}})
    with pytest.raises(FormatError) as e:
        PreparedScene(parse_scene(obj, tmp_path / "s.json"))
    assert e.value.path == str(huge) and "32-bit" in str(e.value)


def test_a_luminaire_multiplier_beyond_float32_is_refused(tmp_path):
    ies = os.path.join(ROOT, "materials", "luminaires", "streetlight.ies")
    obj = scene_dict(lights=[{"type": "luminaire", "file": ies, "position": [0, 3, 0], "multiplier": 1e15}])
    with pytest.raises(FormatError) as e:
        PreparedScene(parse_scene(obj, tmp_path / "s.json"))
    assert e.value.path == ies and e.value.where == "candela"


def test_an_environment_map_too_bright_for_its_intensity_is_refused_naming_the_map(tmp_path):
    sky = tmp_path / "sky.exr"
    write_exr(sky, {"beauty": np.full((4, 8, 3), 1e10, np.float32)})
    obj = scene_dict(environment={"type": "map", "file": "sky.exr", "intensity": 1e6})
    with pytest.raises(FormatError) as e:
        PreparedScene(load_scene(write_scene(tmp_path, obj)))
    assert e.value.path == str(sky) and "32-bit" in str(e.value)
    obj["environment"]["intensity"] = 1.0
    PreparedScene(load_scene(write_scene(tmp_path, obj)))  # the same map at intensity 1 is fine


@pytest.mark.parametrize(
    ("option", "value"), [("--threads", "20000"), ("--exposure", "1e308"), ("--spp", "2147483648"), ("--seed", "-1")]
)
def test_option_ranges_are_checked_before_the_scene_is_rendered(tmp_path, capsys, option, value):
    path = write_scene(tmp_path, scene_dict())
    assert main(["render", path, "--out", str(tmp_path / "o.exr"), "--quiet", option, value]) == 2
    err = capsys.readouterr().err
    assert f"command line ({option})" in err and "Traceback" not in err
    assert not (tmp_path / "o.exr").exists()


def test_tonemap_refuses_an_exposure_whose_scale_overflows():
    with pytest.raises(ValueError, match="stops"):
        images.tonemap(np.ones((1, 1, 3)), exposure_stops=1e308)


FIT_FILES = [
    ("401-digit integer", '{"model": "lambert", "parameters": {"albedo": ' + "9" * 401 + "}}", "parameters.albedo"),
    ("20000 brackets", "[" * 20000 + "]" * 20000, ""),
    ("beyond float32", '{"model": "lambert", "parameters": {"albedo": 1e300}}', "parameters.albedo"),
    ("a boolean", '{"model": "lambert", "parameters": {"albedo": true}}', "parameters.albedo"),
    ("not UTF-8", b'{"model": "\xff"}', "byte 11"),
]


@pytest.mark.parametrize(("case", "text", "where"), FIT_FILES, ids=[c[0] for c in FIT_FILES])
def test_read_fit_names_the_file_and_key_for_values_json_accepts(tmp_path, case, text, where):
    path = tmp_path / "fit.json"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    with pytest.raises(FormatError) as e:
        read_fit(str(path))
    assert e.value.path == str(path) and e.value.where == where


@pytest.mark.parametrize("text", ["[" * 20000 + "]" * 20000, '{"version": ' + "9" * 5000 + "}"])
def test_scene_json_nested_or_huge_is_a_format_error(tmp_path, text):
    path = tmp_path / "s.json"
    path.write_text(text)
    with pytest.raises(FormatError) as e:
        load_scene(path)
    assert e.value.path == str(path)


# ---------------------------------------------------------------- 12: geometry and outputs


def test_a_degenerate_emissive_mesh_is_refused_naming_the_light(tmp_path):
    (tmp_path / "flat.obj").write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")  # collinear: no area
    obj = scene_dict(lights=[{"type": "mesh", "file": "flat.obj", "radiance": 1}])
    path = write_scene(tmp_path, obj)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(FormatError) as e:
            PreparedScene(load_scene(path))
    assert e.value.where == "lights[0]" and "no area" in str(e.value)


def test_a_sphere_too_small_to_tessellate_says_so():
    with pytest.raises(ValueError, match="radius"):
        shapes.sphere(1e-300)
    with pytest.raises(ValueError, match="no triangles"):
        shapes._revolve([shapes._arc((0.0, 0.0), 1e-13, -1.5, 1.5, 0.1)], 8)


def test_a_transform_placing_geometry_beyond_float32_is_refused(tmp_path):
    m = [[1e20, 0, 0, 0], [0, 1e20, 0, 0], [0, 0, 1e20, 0], [0, 0, 0, 1]]
    obj = scene_dict(shapes=[{"type": "sphere", "material": "grey", "transform": {"matrix": m}}])
    with pytest.raises(FormatError) as e:
        PreparedScene(parse_scene(obj, tmp_path / "s.json"))
    assert e.value.where == "shapes[0]"


def test_write_errors_name_the_given_path_not_the_temporary_file(tmp_path):
    target = tmp_path / "a-file" / "out.exr"
    (tmp_path / "a-file").write_text("not a folder")
    with pytest.raises(OSError) as e:
        write_exr(target, {"beauty": np.zeros((1, 1, 3))})
    assert str(e.value).startswith(str(target)) and ".tmp" not in str(e.value)
    with pytest.raises(ValueError, match=str(tmp_path / "n.exr")):
        write_exr(tmp_path / "n.exr", {"beauty": np.full((1, 1, 3), np.nan)})


def test_check_writable_refuses_before_any_work(tmp_path):
    (tmp_path / "f").write_text("")
    atomic.check_writable(tmp_path / "new" / "deeper" / "x.exr")  # folders made later
    atomic.check_writable(tmp_path / "x.exr")
    assert os.listdir(tmp_path) == ["f"]  # the probe leaves nothing behind
    for bad in (tmp_path, tmp_path / "f" / "x.exr", tmp_path / "f" / "sub" / "x.exr"):
        with pytest.raises(OSError) as e:
            atomic.check_writable(bad)
        assert str(e.value).startswith(str(bad)) and "Errno" not in str(e.value)


# ---------------------------------------------------------------- 13: memory


def test_a_render_larger_than_memory_is_refused_up_front(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(prepare, "available_memory", lambda: 1 << 30)
    path = write_scene(tmp_path, scene_dict())
    check_render_memory(load_scene(path))  # 12 x 8 fits
    args = ["render", path, "--out", str(tmp_path / "o.exr"), "--width", "16384", "--height", "16384", "--quiet"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "16384x16384" in err and "GiB" in err and "at most about" in err and "Traceback" not in err


def test_memory_estimate_covers_the_film_and_images():
    assert prepare.render_memory(100, 10) == 1000 * (13 * 8 + 12 * 4)


def test_png_tone_mapping_in_row_chunks_matches_the_whole_image(tmp_path):
    rgb = np.random.default_rng(1).uniform(0, 4, (images.TONEMAP_ROWS * 2 + 3, 5, 3)).astype(np.float32)
    images.write_png(tmp_path / "t.png", rgb, exposure_stops=0.5)
    png = oiio.ImageBuf(str(tmp_path / "t.png")).get_pixels(oiio.UINT8)
    assert np.array_equal(png, images.tonemap(rgb, 0.5, "filmic"))
