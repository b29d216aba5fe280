"""tools/metal_constants.py: samples the spectra at metals.WAVELENGTHS_NM (not its own copy of
650, 550, 450) for every metal of metals.METALS, and reproduces METALS from mitsuba's data."""

import importlib.util
import os

import pytest

from patina.scene import metals
from repo_paths import ROOT


def load_tool():
    spec = importlib.util.spec_from_file_location("metal_constants", os.path.join(ROOT, "tools", "metal_constants.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_samples_at_the_wavelengths_the_module_declares(tmp_path, monkeypatch):
    # spectra whose value is the wavelength itself show where they were sampled
    for metal in metals.METALS:
        for quantity in ("eta", "k"):
            (tmp_path / f"{metal}.{quantity}.spd").write_text("# nm value\n300 300\n900 900\n")
    tool = load_tool()
    assert set(tool.compute(str(tmp_path))) == set(metals.METALS)
    assert tool.compute(str(tmp_path))["Au"] == (metals.WAVELENGTHS_NM, metals.WAVELENGTHS_NM)
    monkeypatch.setattr(tool, "WAVELENGTHS_NM", (700.0, 500.0, 400.0))
    assert tool.compute(str(tmp_path))["Cu"][0] == (700.0, 500.0, 400.0)


def test_reproduces_the_table_from_mitsuba():
    pytest.importorskip("mitsuba")
    tool = load_tool()
    assert tool.compute(tool.mitsuba_ior_folder()) == metals.METALS
