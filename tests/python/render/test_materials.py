"""Scene materials as the renderer takes them (patina.render.materials), here the RGL material:
an RGL .bsdf written by the test-suite writer from an analytic glossy plastic renders under
`path` as the same file converted to .ptab does (within noise and the table's resampling
error); its own warps sample it with less error than the cosine at equal spp; every
integrator renders it; a bad file is one line naming the scene file and the material."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from patina.cli import main
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import parse_scene
from rgl_tables import write_glossy_rgl

SPP = 16


@pytest.fixture(scope="module")
def rgl_file(tmp_path_factory) -> str:
    return write_glossy_rgl(str(tmp_path_factory.mktemp("rgl") / "glossy.bsdf"))


def sphere_scene(material: dict, folder: str, spp: int = SPP, integrator: str = "path", seed: int = 0, floor=False):
    """The material on an analytic sphere under a constant sky and a quad light above it; with
    `floor`, on a grey floor (light between the two: what the radiance cache serves)."""
    obj = {
        "version": 1,
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 32, "width": 24, "height": 24},
        "render": {"spp": spp, "integrator": integrator, "max_depth": 3, "seed": seed},
        "materials": {"shiny": material},
        "shapes": [{"type": "sphere", "material": "shiny", "radius": 1, "analytic": True}],
        "lights": [{"type": "quad", "center": [0.8, 3, 1.5], "u": [0.5, 0, 0], "v": [0, 0, 0.5], "radiance": 20}],
        "environment": {"type": "constant", "radiance": 0.5},
    }
    if floor:
        obj["materials"]["floor"] = {"type": "lambert", "albedo": 0.5}
        plane = {"type": "plane", "material": "floor", "size": [8, 8], "transform": {"translate": [0, -1, 0]}}
        obj["shapes"].append(plane)
    return parse_scene(obj, os.path.join(folder, "scene.json"))


def rgl(file: str, sampling: str = "file") -> dict:
    return {"type": "rgl", "file": file, "sampling": sampling}


def rel_mse(image: np.ndarray, reference: np.ndarray) -> float:
    return float(np.mean((image - reference) ** 2 / (reference**2 + 1e-2)))


@pytest.fixture(scope="module")
def reference(rgl_file) -> np.ndarray:
    """The RGL material converged (1024 spp by its own sampling)."""
    return render(sphere_scene(rgl(rgl_file), os.path.dirname(rgl_file), spp=1024, seed=7)).rgb


def test_the_renderer_takes_the_rgl_kind_with_the_lobe_the_cache_decides_by(rgl_file):
    prepared = PreparedScene(sphere_scene(rgl(rgl_file), os.path.dirname(rgl_file)))
    m = prepared.core_materials[0]  # then the quad light's emitter
    assert m["kind"] == "rgl" and m["sampling"] == "file"
    assert 0.1 <= m["lobe_alpha"] <= 0.3  # the proxy's fit to alpha 0.15
    assert 0.05 < m["albedo"][0] < 1


def test_path_equals_the_file_converted_to_a_ptab_table(rgl_file, reference, tmp_path):
    ptab = str(tmp_path / "glossy.ptab")
    assert main(["convert", rgl_file, ptab]) == 0
    table = render(sphere_scene({"type": "table", "file": ptab}, str(tmp_path), spp=512, seed=3)).rgb
    hit = reference.sum(axis=2) > 0
    assert abs(table[hit].mean() / reference[hit].mean() - 1) < 0.02
    # 4 x 4 pixel blocks: the noise averaged (at 1024 spp they agree within 4%, the highlight's
    # block too; at 512 the highlight's noise is a few % more), the table's resampling error left
    blocks = [a.reshape(6, 4, 6, 4, 3).mean(axis=(1, 3)) for a in (table, reference)]
    np.testing.assert_allclose(blocks[0], blocks[1], rtol=0.1, atol=0.01)


def test_its_own_sampling_has_less_error_than_the_cosine_at_equal_spp(rgl_file, reference):
    folder = os.path.dirname(rgl_file)
    own = render(sphere_scene(rgl(rgl_file), folder, seed=1)).rgb
    cosine = render(sphere_scene(rgl(rgl_file, "cosine"), folder, seed=1)).rgb
    assert np.all(np.isfinite(own)) and np.all(np.isfinite(cosine))
    assert rel_mse(own, reference) < 0.5 * rel_mse(cosine, reference)


@pytest.fixture(scope="module")
def on_the_floor(rgl_file) -> np.ndarray:
    """The RGL sphere on a floor, path traced at 1024 spp."""
    return render(sphere_scene(rgl(rgl_file), os.path.dirname(rgl_file), spp=1024, seed=7, floor=True)).rgb


@pytest.mark.parametrize("integrator", ["direct", "cache", "cache-guided"])
def test_every_integrator_renders_it(rgl_file, on_the_floor, integrator):
    scene = sphere_scene(rgl(rgl_file), os.path.dirname(rgl_file), spp=64, integrator=integrator, floor=True)
    result = render(scene)
    image = result.rgb
    assert np.all(np.isfinite(image)) and image.min() >= 0
    ratio = image.mean() / on_the_floor.mean()
    if integrator == "direct":  # without the light between sphere and floor
        assert 0.7 < ratio < 0.99
    elif integrator == "cache":  # the cache reconstructs: biased, within its error
        assert result.cache_queries > 0 and abs(ratio - 1) < 0.05
    else:  # guiding only moves where the samples go
        assert abs(ratio - 1) < 0.02


def test_a_spectral_file_renders_as_linear_srgb(tmp_path):
    spectral = write_glossy_rgl(str(tmp_path / "spectral.bsdf"), spectral=True)
    result = render(sphere_scene(rgl(spectral), str(tmp_path), spp=4))
    image, hit = result.rgb, np.isfinite(result.depth)  # the sphere's pixels
    assert np.all(np.isfinite(image)) and hit.any()
    red, _, blue = image[hit].mean(axis=0)
    assert red > 1.5 * blue  # the reflectance rises towards the long wavelengths


def test_a_bad_file_is_one_line_naming_the_scene_and_the_material(rgl_file, tmp_path):
    broken = tmp_path / "broken.bsdf"
    broken.write_bytes(open(rgl_file, "rb").read()[:5000])
    scene = tmp_path / "scene.json"
    obj = {
        "version": 1,
        "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 8, "height": 8},
        "materials": {"shiny": {"type": "rgl", "file": "broken.bsdf"}},
        "shapes": [{"type": "sphere", "material": "shiny"}],
    }
    scene.write_text(json.dumps(obj))
    r = subprocess.run(
        [sys.executable, "-m", "patina.cli", "render", str(scene), "--out", str(tmp_path / "x.exr")],
        check=False, capture_output=True, text=True,
    )  # fmt: skip
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2 and len(lines) == 1, r.stderr
    assert str(scene) in lines[0] and "materials.shiny" in lines[0] and "broken.bsdf" in lines[0]
    assert "Traceback" not in r.stderr and not (tmp_path / "x.exr").exists()
