"""The MATERIAL an export starts from: a fit.json, a ranking written by `fit --compare --out`
(its best usable fit), a measured table (any format `patina.load_brdf` reads: not .json), or
`SCENE.json#name`, a scene's material by name. Each becomes a
`Source`: something Patina evaluates (the reference every export is measured against) and,
where the model already is Lambert + GGX or Beckmann lobes with shared shapes, the
AnalyticMaterial that says it exactly; other models are refitted (patina.export.refit)."""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from patina.errors import FormatError
from patina.export.material import DISTRIBUTIONS, AnalyticMaterial, Coat, Lobe
from patina.fitting import FittedModel, read_fit
from patina.fitting.fit_file import MAX_FIT_BYTES
from patina.scene import load_scene
from patina.scene.types import CarpaintMaterial, FitMaterial, LambertMaterial, TableMaterial
from patina.table import load_brdf
from patina.table.spectral import as_linear_srgb


@dataclass
class Source:
    name: str  # the material's name in the written files
    path: str  # the file it came from (and #name for a scene's)
    model: str  # fit.json's model, or the scene material's type
    evaluate: Any  # (wi, wo) -> (n, 3) RGB, the reference
    exact: AnalyticMaterial | None  # the material itself, when no refit is needed
    fitted: FittedModel | None = None
    table: Any = None  # a measured table (Brdf): written as `measured` where the target has it
    two_sided: bool = False  # a scene's table material: lit from both sides


def _name(path: str) -> str:
    stem = os.path.splitext(os.path.basename(path))[0]
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in stem) or "material"


def analytic_from_fit(fitted: FittedModel, name: str, source: str) -> AnalyticMaterial | None:
    """The fit as an AnalyticMaterial when it is one (Lambert + GGX or Beckmann lobes with one
    roughness for the three channels), else None."""
    space = fitted.space
    if space.lobe not in DISTRIBUTIONS or space.per_channel:
        return None
    p = dict(zip(space.names, fitted.values))
    lobes = []
    for k in range(space.lobes):
        tag = "" if space.lobes == 1 else f"_{k + 1}"
        lobes.append(Lobe(space.lobe, p[f"alpha{tag}"], tuple(p[f"f0{tag}_{c}"] for c in "rgb")))
    coat = Coat(p["coat_alpha"], p["coat_eta"]) if space.coat else None
    diffuse = tuple(p[f"rho_{c}"] for c in "rgb")
    return AnalyticMaterial(name, diffuse, tuple(lobes), coat, False, fitted.model, source)


def _best_usable(path: str) -> dict[str, Any] | None:
    """From a ranking (`fit --compare --out`), the first entry marked usable; None for a plain fit.json."""
    with open(path, "rb") as f:
        doc = json.loads(f.read(MAX_FIT_BYTES + 1).decode("utf-8-sig"))  # read_fit has checked it already
    ranking = doc.get("ranking")
    if not isinstance(ranking, list):
        return None
    for index, entry in enumerate(ranking):
        if isinstance(entry, dict) and entry.get("usable") is True:
            if not isinstance(entry.get("model"), str) or not isinstance(entry.get("parameters"), dict):
                raise FormatError(path, f"ranking[{index}]", "missing its model or parameters")
            return {**entry, "index": index}
    raise FormatError(path, "ranking", "no fit in the ranking is usable: nothing worth exporting")


def _fit_source(path: str, name: str | None = None, where: str = "") -> Source:
    fitted = read_fit(path)
    best = _best_usable(path)
    if best is not None and best["index"] > 0:
        place = f"ranking[{best['index']}].parameters"
        values = best["parameters"]
        for key, value in values.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise FormatError(path, f"{place}.{key}", "must be a finite number")
        try:
            fitted = FittedModel(best["model"], {str(k): float(v) for k, v in values.items()})
        except ValueError as e:
            raise FormatError(path, place, str(e)) from None
    name = name or _name(path)
    shown = path + where
    return Source(name, shown, fitted.model, fitted.eval, analytic_from_fit(fitted, name, shown), fitted)


def _table_source(path: str, name: str | None = None, shown: str | None = None, two_sided: bool = False) -> Source:
    """A measured table (any format load_brdf reads), its values in linear sRGB the reference."""
    brdf = load_brdf(path)
    rgb = as_linear_srgb(brdf)

    def evaluate(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        return np.asarray(rgb.eval(wi, wo), np.float64)

    model = f"table ({brdf.source_format})"
    return Source(name or _name(path), shown or path, model, evaluate, None, None, brdf, two_sided)


def _scene_source(path: str, material: str) -> Source:
    scene = load_scene(path)
    if material not in scene.materials:
        known = ", ".join(sorted(scene.materials)) or "none"
        raise FormatError(path, f"materials.{material}", f"no such material (the scene has: {known})")
    m = scene.materials[material]
    shown = f"{path}#{material}"
    if isinstance(m, LambertMaterial):
        exact = AnalyticMaterial(material, tuple(m.albedo), (), None, m.two_sided, "lambert", shown)
        return Source(material, shown, "lambert", exact.eval, exact)
    if isinstance(m, CarpaintMaterial) and isinstance(m.base, LambertMaterial):
        if tuple(m.coat.thickness_tint) != (1.0, 1.0, 1.0):
            raise FormatError(path, f"materials.{material}.coat", "a thickness_tint has no export here")
        coat = Coat(max(m.coat.roughness, 1e-3), m.coat.eta)
        exact = AnalyticMaterial(material, tuple(m.base.albedo), (), coat, m.two_sided, "carpaint", shown)
        return Source(material, shown, "carpaint", exact.eval, exact)
    if isinstance(m, TableMaterial) and m.scale == 1.0 and tuple(m.tint) == (1.0, 1.0, 1.0):
        return _table_source(m.file, material, f"{m.file} (materials.{material} of {path})", m.two_sided)
    if isinstance(m, FitMaterial) and m.scale == 1.0 and tuple(m.tint) == (1.0, 1.0, 1.0):
        src = _fit_source(m.file, material, f" (materials.{material} of {path})")
        if src.exact is not None:
            src.exact = replace(src.exact, two_sided=m.two_sided)
        return src
    raise FormatError(
        path,
        f"materials.{material}",
        f"a {m.type} material has no export (supported: fit or table without scale or tint, lambert, "
        "carpaint over lambert)",
    )


def load_source(spec: str) -> Source:
    """MATERIAL as the command line gives it -> Source; FormatError for anything unreadable."""
    path, hash_, material = spec.partition("#")
    if hash_:
        if not material:
            raise FormatError(path, "#", "give a material name after '#' (SCENE.json#name)")
        return _scene_source(path, material)
    if not path.lower().endswith(".json"):
        return _table_source(path)
    return _fit_source(path)


def sample_pairs(count: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Direction pairs uniform over the upper hemisphere's solid angle, both sides, (n, 3) each."""
    rng = np.random.default_rng(seed)

    def hemisphere(n: int) -> np.ndarray:
        z = rng.uniform(0.02, 1.0, n)
        phi = rng.uniform(0, 2 * np.pi, n)
        r = np.sqrt(1 - z * z)
        return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)

    return hemisphere(count), hemisphere(count)
