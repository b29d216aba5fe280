"""A table's dependence on the azimuth (python/patina/table/isotropy.py) tells an isotropic
material on a four-dimensional grid from an anisotropic one."""

from __future__ import annotations

import os

import patina
from format_writers import utia_values
from patina.synthetic.analytic import plastic
from patina.table.isotropy import ISOTROPIC_WITHIN, azimuth_dependence, is_anisotropic
from repo_paths import ROOT


def test_an_isotropic_plastic_on_a_utia_grid_is_isotropic(tmp_path):
    path = tmp_path / "m001_plastic.bin"
    path.write_bytes(
        utia_values(plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)).astype("<f8").tobytes()
    )
    table = patina.load_brdf(str(path))
    assert table.parametrization == "anisotropic"
    assert azimuth_dependence(table) < 0.1 * ISOTROPIC_WITHIN and not is_anisotropic(table)


def test_brushed_metal_and_a_klems_shade_are_anisotropic():
    brushed = patina.load_brdf(os.path.join(ROOT, "materials", "samples", "brushed-metal.astm"))
    shade = patina.load_brdf(os.path.join(ROOT, "materials", "radiance", "klems_aniso_high.xml"))
    assert azimuth_dependence(brushed) > 0.3
    assert 1.5 * ISOTROPIC_WITHIN < azimuth_dependence(shade) < 0.3 and is_anisotropic(shade)


def test_isotropic_parametrizations_are_isotropic_by_construction():
    table = patina.load_brdf(os.path.join(ROOT, "materials", "red-plastic-iso.ptab"))
    assert table.parametrization != "anisotropic" and azimuth_dependence(table) == 0.0
