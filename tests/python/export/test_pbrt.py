"""pbrt-v4 export: the material block parsed back gives the parameters (alpha unremapped)."""

from __future__ import annotations

import re

import pytest

from export_helpers import COATED, GGX, LAMBERT_COAT, METAL, TWO_GGX
from patina.export.material import AnalyticMaterial
from patina.export.pbrt import to_pbrt
from patina.export.principled import f0_from_ior


def parse(text: str) -> tuple[str, dict[str, list]]:
    """A MakeNamedMaterial block -> (type, {parameter: values}), as pbrt's tokenizer splits it."""
    params: dict[str, list] = {}
    for kind, name, value in re.findall(r'"(\w+) ([\w.]+)" (\[[^\]]*\]|"[^"]*"|\S+)', text):
        values = value.strip("[]").split()
        params[name] = [v.strip('"') for v in values] if kind in ("string", "bool") else [float(v) for v in values]
    return params.pop("type")[0], params


def test_lambert_plus_dielectric_lobe_is_coateddiffuse():
    kind, p = parse(to_pbrt(GGX))
    assert kind == "coateddiffuse" and p["remaproughness"] == ["false"]
    assert p["roughness"][0] == pytest.approx(GGX.lobes[0].alpha)
    assert f0_from_ior(p["eta"][0]) == pytest.approx(sum(GGX.lobes[0].f0) / 3, rel=1e-4)
    assert p["reflectance"] == pytest.approx(list(GGX.diffuse))


def test_metal_is_conductor_with_reflectance():
    kind, p = parse(to_pbrt(METAL))
    assert kind == "conductor" and p["reflectance"] == pytest.approx(list(METAL.lobes[0].f0))


def test_coat_index_and_roughness():
    notes: list[str] = []
    kind, p = parse(to_pbrt(COATED, notes))
    assert kind == "coateddiffuse" and p["eta"][0] == pytest.approx(COATED.coat.eta)
    assert p["roughness"][0] == pytest.approx(COATED.coat.alpha) and notes
    assert parse(to_pbrt(LAMBERT_COAT))[0] == "coateddiffuse"
    assert parse(to_pbrt(AnalyticMaterial("white", (0.8, 0.8, 0.8))))[0] == "diffuse"


def test_two_lobes_need_a_refit():
    with pytest.raises(ValueError, match="refit"):
        to_pbrt(TWO_GGX)
