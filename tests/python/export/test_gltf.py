"""glTF export: the Khronos validator finds no errors (where Node and the validator from
tools/gltf_validator are installed), and pygltflib reads the parameters back."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from export_helpers import COATED, GGX, METAL
from patina.export.gltf import write_gltf
from patina.export.principled import f0_from_ior
from repo_paths import ROOT

pygltflib = pytest.importorskip("pygltflib")
VALIDATOR = Path(ROOT) / "tools" / "gltf_validator"


def _validate(path) -> dict:
    node = shutil.which("node")
    if node is None or not (VALIDATOR / "node_modules" / "gltf-validator").is_dir():
        pytest.skip("Node or the glTF validator (npm install in tools/gltf_validator) is absent")
    run = subprocess.run(
        [node, str(VALIDATOR / "validate.js"), str(path)], capture_output=True, text=True, timeout=60, check=False
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


@pytest.mark.parametrize("suffix", [".glb", ".gltf"])
@pytest.mark.parametrize("material", [GGX, COATED, METAL], ids=lambda m: m.name)
def test_validator_reports_no_errors(tmp_path, material, suffix):
    path = tmp_path / f"m{suffix}"
    write_gltf(material, str(path))
    report = _validate(path)
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["issues"]["numWarnings"] == 0, report["issues"]["messages"]


def test_parameters_round_trip(tmp_path):
    path = tmp_path / "m.glb"
    write_gltf(COATED, str(path))
    doc = pygltflib.GLTF2().load(str(path))
    (m,) = doc.materials
    lobe = COATED.lobes[0]
    assert m.pbrMetallicRoughness.roughnessFactor**2 == pytest.approx(lobe.alpha, rel=1e-6)
    assert m.pbrMetallicRoughness.baseColorFactor[:3] == pytest.approx(list(COATED.diffuse))
    ior = m.extensions["KHR_materials_ior"]["ior"]
    tint = m.extensions["KHR_materials_specular"]["specularColorFactor"]
    assert [f0_from_ior(ior) * c for c in tint] == pytest.approx(list(lobe.f0), rel=1e-5)
    coat = m.extensions["KHR_materials_clearcoat"]
    assert coat["clearcoatRoughnessFactor"] ** 2 == pytest.approx(COATED.coat.alpha, rel=1e-6)
    assert sorted(doc.extensionsUsed) == ["KHR_materials_clearcoat", "KHR_materials_ior", "KHR_materials_specular"]
