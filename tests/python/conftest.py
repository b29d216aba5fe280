from __future__ import annotations

import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))

import patina
from patina.synthetic.analytic import merl_raw, plastic, write_merl
from patina.widths import WIDTHS as ALL_WIDTHS
from repo_paths import ROOT

# every width patina knows that this CPU runs (16 only with AVX-512)
WIDTHS = [w for w in ALL_WIDTHS if patina._core.width_supported(w)]


@pytest.fixture(scope="session")
def bundled_ptab() -> str:
    return os.path.join(ROOT, "materials", "red-plastic-iso.ptab")


@pytest.fixture(scope="session")
def bundled_astm() -> str:
    return os.path.join(ROOT, "materials", "red-plastic-iso.astm")


@pytest.fixture(scope="session")
def merl_model():
    return plastic(diffuse=(0.3, 0.5, 0.2), specular=0.05, roughness=0.3)


@pytest.fixture(scope="session")
def merl_raw_values(merl_model) -> np.ndarray:
    return merl_raw(merl_model)


@pytest.fixture(scope="session")
def merl_file(tmp_path_factory, merl_raw_values) -> str:
    """A MERL .binary written from an analytic BRDF, with a few missing-data markers."""
    raw = merl_raw_values.copy()
    raw[:, 5, 40, 100] = -1.0  # the reference data marks unmeasured bins with negative values
    raw[:, 60, 10, 7] = -1.0
    path = str(tmp_path_factory.mktemp("merl") / "synthetic.binary")
    write_merl(path, raw)
    return path


def load_or_format_error(content: bytes, filename: str, load, check) -> None:
    """Saves `content` as `filename` in a fresh folder and loads it with `load(path)`: either a
    FormatError naming the file, or a result that passes `check(result)` -- never anything else
    (the parsers' fuzz tests)."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, filename)
        with open(path, "wb") as f:
            f.write(content)
        try:
            result = load(path)
        except patina.FormatError as e:
            assert e.path == path and path in str(e)
            return
        check(result)
