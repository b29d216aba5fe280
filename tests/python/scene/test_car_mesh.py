"""The car of materials/scenes/cache-car.json: its meshes are what tools/make_car_mesh.py
writes (byte for byte), lean, and closed or open only where the cabin meets the roof, with
their triangles wound outwards (the renderer's materials are one-sided and its normals come
from the winding)."""

from __future__ import annotations

import importlib.util
import os

import numpy as np
import pytest

from patina.geometry.shapes import from_file
from repo_paths import ROOT

SCENES = os.path.join(ROOT, "materials", "scenes")
FILES = ("cache-car-body.obj", "cache-car-windows.obj", "cache-car-wheels.obj")


@pytest.fixture(scope="module")
def tool():
    spec = importlib.util.spec_from_file_location("make_car_mesh", os.path.join(ROOT, "tools", "make_car_mesh.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_bundled_files_are_the_generators_output(tool):
    meshes = tool.car_meshes()
    assert set(meshes) == set(FILES)
    for name, (vertices, triangles) in meshes.items():
        with open(os.path.join(SCENES, name), encoding="utf-8") as f:
            assert f.read() == tool.obj_text(name, vertices, triangles), name


def test_the_car_is_lean_and_car_sized(tool):
    meshes = tool.car_meshes()
    assert 2000 <= sum(len(t) for _, t in meshes.values()) <= 8000
    everything = np.concatenate([v for v, _ in meshes.values()])
    size = everything.max(axis=0) - everything.min(axis=0)
    np.testing.assert_allclose(size, [4.3, 1.38, 1.82], atol=0.06)  # length, height, width over the tyres
    assert everything[:, 1].min() == pytest.approx(0.0, abs=1e-6)  # the tyres stand on the floor


@pytest.mark.parametrize("name", FILES)
def test_normals_point_outwards(name):
    # each vertex normal points away from its part's centre: the wheels' from their axle's
    # middle, the body's and the cabin's from the car's centre line at the vertex's height
    mesh = from_file(os.path.join(SCENES, name))
    v, n = np.asarray(mesh.vertices, np.float64), np.asarray(mesh.normals, np.float64)
    if name == "cache-car-wheels.obj":
        centre = np.stack([np.sign(v[:, 0]) * 1.33, np.full(len(v), 0.33), np.sign(v[:, 2]) * 0.8], axis=1)
    else:
        centre = np.stack([np.clip(v[:, 0], -1.0, 0.5), np.full(len(v), 0.8), np.zeros(len(v))], axis=1)
    outward = np.sum((v - centre) * n, axis=1)
    assert np.mean(outward > 0) > 0.97, np.mean(outward > 0)
