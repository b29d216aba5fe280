"""Measured tables out (python/patina/export/measured.py): Mitsuba 3's `measured` plugin
(scalar_spectral, from the installed mitsuba package) evaluates the written spectral file in
agreement with Patina's evaluation of the source table, within the format's resampling; the
Mitsuba and pbrt-v4 scene files name the tensor file written beside them; `--to rgl` for a fit."""

from __future__ import annotations

import json
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from export_helpers import GGX_FIT, write_json
from patina.cli import main
from patina.export.measured import MITSUBA_WAVELENGTHS, mitsuba_measured_eval, mitsuba_measured_xml
from patina.export.rgb_upsampling import upsample
from patina.export.rgl import table_source, write_rgl_file
from patina.table.formats.rgl import error_pairs
from patina.table.formats.rgl_brdf import read_rgl_brdf
from repo_paths import ROOT
from rgl_tables import plastic_table


@pytest.fixture(scope="module")
def table_file(tmp_path_factory) -> str:
    path = str(tmp_path_factory.mktemp("measured") / "plastic.ptab")
    plastic_table().save(path)
    return path


def _relative(got: np.ndarray, want: np.ndarray) -> np.ndarray:
    floor = 1e-3 * float(np.median(np.abs(want)))
    return (np.abs(got - want) / np.maximum(np.abs(want), floor)).max(axis=1)


def test_mitsuba_measured_agrees_with_patinas_evaluation_of_the_source(table_file, tmp_path, capsys):
    pytest.importorskip("mitsuba")
    table = plastic_table()
    out = str(tmp_path / "plastic.bsdf")
    write_rgl_file(table_source(table, table_file), out)
    wi, wo = error_pairs(1500, seed=3)
    keep = (wi[:, 2] > np.cos(np.radians(85))) & (wo[:, 2] > np.cos(np.radians(80)))
    wi, wo = wi[keep], wo[keep]
    mitsuba = mitsuba_measured_eval(out, wi, wo, spectral=True)
    # the same file by Patina's evaluator of the format (f: its f cos(theta_o) over the cosine): only float32 apart
    same_file = upsample(read_rgl_brdf(out).eval(wi, wo), MITSUBA_WAVELENGTHS)
    # the source table, upsampled as the file's spectra were
    source = upsample(np.asarray(table.eval(wi, wo), np.float64), MITSUBA_WAVELENGTHS)
    rel_file, rel_source = _relative(mitsuba, same_file), _relative(mitsuba, source)
    print(
        f"\nMitsuba measured (scalar_spectral) at {len(wi)} pairs: against Patina's reading of the file "
        f"median {np.median(rel_file):.2g}, 95% {np.percentile(rel_file, 95):.2g}; against the source table "
        f"median {np.median(rel_source):.2g}, 95% {np.percentile(rel_source, 95):.2g}"
    )
    assert np.median(rel_file) < 0.01 and np.percentile(rel_file, 95) < 0.03
    assert np.median(rel_source) < 0.01 and np.percentile(rel_source, 95) < 0.15


def test_table_to_mitsuba_and_pbrt_writes_the_tensor_file_beside(table_file, tmp_path, capsys):
    pytest.importorskip("mitsuba")
    xml = tmp_path / "plastic.xml"
    assert main(["export", table_file, "--to", "mitsuba", "--out", str(xml)]) == 0
    assert 'type="measured"' in xml.read_text() and 'value="plastic.bsdf"' in xml.read_text()
    sidecar = json.loads((tmp_path / "plastic.xml.export.json").read_text())
    assert sidecar["tensor_file"] == str(tmp_path / "plastic.bsdf")
    assert sidecar["target_error_against_source"]["evaluator"] == "mitsuba scalar_spectral measured"
    assert sidecar["target_error_against_source"]["relative_error_median"] < 0.01
    assert "as mitsuba scalar_spectral measured evaluates it" in capsys.readouterr().out
    import mitsuba as mi

    mi.set_variant("scalar_spectral")
    assert mi.load_file(str(xml)) is not None  # the XML finds its tensor file by the relative name
    # pbrt beside it under another stem; the same stem is refused (its tensor file exists)
    assert main(["export", table_file, "--to", "pbrt", "--out", str(tmp_path / "plastic.pbrt")]) == 2
    assert "plastic.bsdf: exists; pass --force" in capsys.readouterr().err
    pbrt = tmp_path / "plastic_pbrt.pbrt"
    assert main(["export", table_file, "--to", "pbrt", "--out", str(pbrt)]) == 0
    text = pbrt.read_text()
    assert '"string type" "measured"' in text and '"string filename" "plastic_pbrt.bsdf"' in text
    assert read_rgl_brdf(str(tmp_path / "plastic_pbrt.bsdf")).channel_kind == "spectral"


def test_rgb_channels_for_mitsubas_rgb_variants_and_refused_for_pbrt(table_file, tmp_path, capsys):
    out = tmp_path / "p.bsdf"
    assert main(["export", table_file, "--to", "rgl", "--channels", "rgb", "--out", str(out)]) == 0
    assert read_rgl_brdf(str(out)).channel_kind == "rgb"
    capsys.readouterr()
    assert main(["export", table_file, "--to", "pbrt", "--channels", "rgb", "--out", str(tmp_path / "q.pbrt")]) == 2
    assert "spectral files only" in capsys.readouterr().err
    assert not os.path.exists(tmp_path / "q.pbrt") and not os.path.exists(tmp_path / "q.bsdf")


def test_a_fit_to_rgl_is_the_fit_evaluated_densely(tmp_path, capsys):
    fit = write_json(tmp_path / "ggx.json", GGX_FIT)
    out = tmp_path / "ggx.bsdf"
    assert main(["export", fit, "--to", "rgl", "--channels", "rgb", "--out", str(out)]) == 0
    sidecar = json.loads((tmp_path / "ggx.bsdf.export.json").read_text())
    assert sidecar["error_against_source"]["relative_error_median"] < 0.01
    assert "read back against" in capsys.readouterr().out


def test_mitsuba_renders_the_written_spectral_file_as_patina_evaluates_the_table(tmp_path):
    """A plane under a directional light (D65, irradiance 1) seen by a camera, rendered by Mitsuba
    (scalar_spectral, direct lighting): every pixel is f(to the camera, to the light) cos(theta_light),
    which Patina's evaluation of the source table gives at the pixel's surface point (an AOV)."""
    mi = pytest.importorskip("mitsuba")
    table = plastic_table()
    out = str(tmp_path / "plastic.bsdf")
    write_rgl_file(table_source(table, "plastic.ptab"), out)
    mi.set_variant("scalar_spectral")
    camera = np.array([0.0, -1.5, 2.5])
    light = np.array([0.3, 0.5, -1.0]) / np.linalg.norm([0.3, 0.5, -1.0])  # the direction light travels
    scene = mi.load_dict({
        "type": "scene",
        "integrator": {"type": "aov", "aovs": "pp:position", "image": {"type": "direct"}},
        "sensor": {
            "type": "perspective", "fov": 45,
            "to_world": mi.ScalarTransform4f().look_at(origin=camera.tolist(), target=[0, 0, 0], up=[0, 0, 1]),
            "film": {"type": "hdrfilm", "width": 40, "height": 40, "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": 16},
        },
        "plane": {
            "type": "rectangle", "to_world": mi.ScalarTransform4f().scale([10, 10, 1]),
            "bsdf": {"type": "measured", "filename": out},
        },
        "sun": {"type": "directional", "direction": light.tolist(), "irradiance": {"type": "d65", "scale": 1.0}},
    })  # fmt: skip
    image = np.array(mi.render(scene)).reshape(-1, 6)
    rendered, position = image[:, :3], image[:, 3:6]
    to_camera = camera - position
    to_camera /= np.linalg.norm(to_camera, axis=1, keepdims=True)
    to_light = np.repeat(-light[None], len(position), axis=0)
    want = np.asarray(table.eval(to_camera, to_light), np.float64) * to_light[:, 2:3]
    # the image as a whole: within 2 % (a file without the cosine would be 14 % brighter here)
    assert np.allclose(rendered.mean(axis=0) / want.mean(axis=0), 1.0, atol=0.02)
    # each pixel: within the colour noise of 16 wavelength samples per pixel
    rel = np.abs(rendered - want).max(axis=1) / want.max(axis=1)
    assert np.median(rel) < 0.08 and np.percentile(rel, 95) < 0.2


@pytest.mark.parametrize(
    ("target", "extra", "message"),
    [
        ("rgl", ["--table", "TABLE"], "--table is for an analytic export's refit"),
        ("materialx", ["--channels", "rgb"], "--channels is for an RGL tensor file"),
    ],
)
def test_options_that_do_not_apply_are_refused_in_one_line(table_file, tmp_path, capsys, target, extra, message):
    fit = write_json(tmp_path / "ggx.json", GGX_FIT)
    out = tmp_path / f"ggx.{'bsdf' if target == 'rgl' else 'mtlx'}"
    extra = [table_file if word == "TABLE" else word for word in extra]
    assert main(["export", fit, "--to", target, "--out", str(out), *extra]) == 2
    errors = [line for line in capsys.readouterr().err.splitlines() if line.startswith("patina")]
    assert len(errors) == 1 and message in errors[0]
    assert sorted(os.listdir(tmp_path)) == ["ggx.json"]


def test_a_scenes_table_material_is_exported_as_its_table(tmp_path, capsys):
    scene = os.path.join(ROOT, "materials", "scenes", "cache-room.json")
    out = tmp_path / "wall.bsdf"
    assert main(["export", f"{scene}#feature-wall", "--to", "rgl", "--channels", "rgb", "--out", str(out)]) == 0
    sidecar = json.loads((tmp_path / "wall.bsdf.export.json").read_text())
    assert "red-plastic-iso.ptab (materials.feature-wall of" in sidecar["source"]
    assert sidecar["source_model"] == "table (ptab)"
    assert sidecar["error_against_source"]["relative_error_median"] < 0.02


def test_a_two_sided_material_is_measured_inside_twosided(table_file, tmp_path):
    mi = pytest.importorskip("mitsuba")
    out = tmp_path / "p.bsdf"
    write_rgl_file(table_source(plastic_table(), table_file), str(out), "rgb")
    xml = tmp_path / "p.xml"
    xml.write_text(mitsuba_measured_xml("p--q", str(out), "a--b.ptab", two_sided=True))
    mi.set_variant("scalar_rgb")
    assert isinstance(mi.load_file(str(xml)), mi.Scene)  # a '--' in the names leaves the comment whole
    element = ET.parse(xml).getroot().find("bsdf")
    element.set("version", "3.5.0")
    bsdf = mi.load_string(ET.tostring(element, encoding="unicode"))
    ctx, si = mi.BSDFContext(), mi.SurfaceInteraction3f()
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    si.wi = mi.Vector3f(0.3, 0.0, -0.954)  # from below: twosided mirrors it onto the front
    back = np.array(bsdf.eval(ctx, si, mi.Vector3f(-0.3, 0.1, -0.949)))
    si.wi = mi.Vector3f(0.3, 0.0, 0.954)
    front = np.array(bsdf.eval(ctx, si, mi.Vector3f(-0.3, 0.1, 0.949)))
    assert np.all(front > 0) and np.allclose(back, front, rtol=1e-5)
