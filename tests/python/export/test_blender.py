"""Blender export: the script sets the Principled BSDF's inputs (run against a stand-in for
`bpy` always, and under the real `bpy` module when it is installed)."""

from __future__ import annotations

import importlib.util
import types

import pytest

from export_helpers import COATED
from patina.export.blender import to_blender_script
from patina.export.principled import f0_from_ior


class _Input:
    default_value = None


class _Inputs(dict):
    def __missing__(self, key):
        self[key] = _Input()
        return self[key]


def _stand_in_bpy():
    bsdf = types.SimpleNamespace(inputs=_Inputs())
    nodes = {"Principled BSDF": bsdf}
    tree = types.SimpleNamespace(nodes=types.SimpleNamespace(get=nodes.get, new=lambda kind: bsdf))
    material = types.SimpleNamespace(node_tree=tree)
    materials = types.SimpleNamespace(get=lambda name: material, new=lambda name: material)
    return types.SimpleNamespace(data=types.SimpleNamespace(materials=materials)), bsdf, material


def test_script_sets_the_principled_inputs(monkeypatch):
    import sys

    bpy, bsdf, material = _stand_in_bpy()
    monkeypatch.setitem(sys.modules, "bpy", bpy)
    exec(compile(to_blender_script(COATED), "material.py", "exec"), {})
    values = {k: v.default_value for k, v in bsdf.inputs.items()}
    lobe = COATED.lobes[0]
    assert values["Roughness"] ** 2 == pytest.approx(lobe.alpha, rel=1e-4)
    tinted = [f0_from_ior(values["IOR"]) * c for c in values["Specular Tint"][:3]]
    assert tinted == pytest.approx(list(lobe.f0), rel=1e-3)
    assert values["Coat Roughness"] ** 2 == pytest.approx(COATED.coat.alpha, rel=1e-4)
    assert values["Coat IOR"] == pytest.approx(COATED.coat.eta) and values["Coat Weight"] == 1
    assert material.use_nodes and material.use_backface_culling


@pytest.mark.skipif(importlib.util.find_spec("bpy") is None, reason="bpy (Blender as a module) is not installed")
def test_script_runs_under_bpy():
    import bpy

    exec(compile(to_blender_script(COATED), "material.py", "exec"), {})
    bsdf = bpy.data.materials["coated"].node_tree.nodes["Principled BSDF"]
    assert bsdf.inputs["Coat IOR"].default_value == pytest.approx(COATED.coat.eta)
