"""A fit exported to Mitsuba 3 renders as Patina renders the fit: the same scene (a sphere in
the fitted material under a point light and a constant sky), Patina's image against Mitsuba's
image of the converted scene, whose material is `patina export`'s Mitsuba BSDF
(patina.scene.mitsuba converts a fit through the export's mapping). The two renderers' noise
differs; the images agree when their difference is no larger than the noise between two
Patina renders of different seeds (relMSE)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from export_helpers import GGX_FIT, write_json
from patina.render.run import render
from patina.scene.mitsuba import to_mitsuba
from patina.scene.reading import parse_scene

mi = pytest.importorskip("mitsuba")


def _scene(folder, fit: str):
    return parse_scene(
        {
            "version": 1,
            "camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov": 30, "width": 32, "height": 24},
            "render": {"spp": 256, "integrator": "path", "max_depth": 3},
            "materials": {"paint": {"type": "fit", "file": fit}},
            "shapes": [{"type": "sphere", "material": "paint"}],
            "lights": [{"type": "point", "position": [2.0, 2.5, 3.0], "intensity": [20.0, 20.0, 20.0]}],
            "environment": {"type": "constant", "radiance": [0.3, 0.3, 0.35]},
        },
        str(folder / "scene.json"),
    )


def relmse(image: np.ndarray, reference: np.ndarray) -> float:
    return float(np.mean((image - reference) ** 2 / (reference**2 + 1e-2)))


def test_exported_fit_renders_in_mitsuba_as_in_patina(tmp_path):
    mi.set_variant("scalar_rgb")
    scene = _scene(tmp_path, write_json(tmp_path / "fit.json", GGX_FIT))
    ours = render(scene).rgb.astype(np.float64)
    reseeded = dataclasses.replace(scene, render=dataclasses.replace(scene.render, seed=scene.render.seed + 1))
    ours_again = render(reseeded).rgb.astype(np.float64)
    theirs = np.asarray(mi.render(mi.load_dict(to_mitsuba(scene))), np.float64)
    noise = relmse(ours_again, ours)
    difference = relmse(theirs, ours)
    print(f"\nrelMSE Mitsuba vs Patina {difference:.3g}; Patina vs Patina (another seed) {noise:.3g}")
    assert noise > 0  # the renders are noisy: the comparison measures something
    assert difference < 3 * noise
    np.testing.assert_allclose(theirs.mean(axis=(0, 1)), ours.mean(axis=(0, 1)), rtol=0.02)
