"""Tensor-tree BSDF XML as a table (python/patina/table/formats/tensor_tree_table.py):
a known plastic written as TensorTree3 and TensorTree4 comes back within the trees' own
cell size, its highlight in the mirror direction, the error reported in the provenance;
front or back; X, Y, Z blocks as an XYZ table."""

from __future__ import annotations

import numpy as np
import pytest

import patina
from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.angles import angles_to_directions
from tensor_tree_writer import UNUSED, tree_document, tree_grid, tree_text

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.35)


def _document(tmp_path, rank: int, log2: int, blocks=(("Reflection Front", "Visible", 1),)) -> str:
    text = tree_document([(d, label, tree_text(tree_grid(MODEL, rank, log2, c), 1)) for d, label, c in blocks], rank)
    path = tmp_path / f"tree{rank}.xml"
    path.write_text(text)
    return str(path)


def _relative_error(brdf, channel: int = 1) -> np.ndarray:
    rng = np.random.default_rng(3)
    ti, to = rng.uniform(0.05, np.radians(70), (2, 4000))
    pi, po = rng.uniform(0, 2 * np.pi, (2, 4000))
    wi, wo = angles_to_directions(ti, pi), angles_to_directions(to, po)
    want = MODEL(wi, wo)[:, channel]
    return np.abs(brdf.eval(wi, wo)[:, 0] - want) / want


@pytest.mark.parametrize(("rank", "log2", "median"), [(3, 5, 0.006), (4, 4, 0.012)])
def test_a_plastic_comes_back_within_the_cell_size(tmp_path, rank, log2, median):
    brdf = patina.load_brdf(_document(tmp_path, rank, log2))
    info = brdf.info()
    assert info["format"] == "window_xml" and brdf.channel_kind == "mono"
    assert brdf.parametrization == ("isotropic" if rank == 3 else "anisotropic")
    assert f"TensorTree{rank}, LBNL/Shirley-Chiu, reflection front" in info["provenance"]
    assert "relative difference to the tree at 8192 pairs: median" in info["provenance"]
    error = _relative_error(brdf)
    assert np.median(error) < median and np.percentile(error, 95) < 0.08
    assert brdf.table.values.max() < UNUSED  # TensorTree3's unused half is never read


@pytest.mark.parametrize("rank", [3, 4])
def test_the_highlight_is_in_the_mirror_direction(tmp_path, rank):
    glossy = plastic(diffuse=(0.05,), specular=0.5, roughness=0.15)
    path = tmp_path / "glossy.xml"
    path.write_text(
        tree_document(
            [("Reflection Front", "Visible", tree_text(tree_grid(glossy, rank, 5 if rank == 3 else 4), 2))], rank
        )
    )
    brdf = patina.load_brdf(str(path))
    wi = angles_to_directions(np.radians(40.0), np.radians(30.0))[None]
    phi = np.radians(np.arange(0, 360, 5.0))
    wo = angles_to_directions(np.full(phi.size, np.radians(40.0)), phi)
    values = brdf.eval(np.repeat(wi, phi.size, axis=0), wo)[:, 0]
    assert abs(np.degrees(phi[np.argmax(values)]) - 210.0) <= 10.0


def test_back_side_xyz_and_transmission_skipped(tmp_path):
    blocks = [("Transmission Front", "Visible", 1), ("Reflection Back", "CIE-X", 0), ("Reflection Back", "CIE-Y", 1),
              ("Reflection Back", "CIE-Z", 2)]  # fmt: skip
    path = _document(tmp_path, 3, 4, blocks)
    with pytest.raises(FormatError, match="no 'Reflection Front' block"):
        patina.load_brdf(path)
    from patina.table.formats.window_xml import read_window_xml

    data = read_window_xml(path, side="back")
    assert data.channel_kind == "xyz" and data.values.shape[-1] == 3
    assert "skipped: transmission front (Visible)" in data.provenance


def test_an_unknown_basis_or_rank_is_refused(tmp_path):
    path = tmp_path / "b.xml"
    path.write_text(tree_document([("Reflection Front", "Visible", "{ 1 }")], 3, basis="LBNL/Klems Full"))
    with pytest.raises(FormatError, match="'LBNL/Klems Full': a tensor tree needs LBNL/Shirley-Chiu"):
        patina.load_brdf(str(path))
    path.write_text(tree_document([("Reflection Front", "Visible", "{ 1 }")], 5))
    with pytest.raises(FormatError, match="TensorTree5: expected TensorTree3 or TensorTree4"):
        patina.load_brdf(str(path))


def test_bundled_real_tensor_tree_file():
    """materials/radiance/blindsT3.xml (LBNL pyradiance's samples, genBSDF -t3 5): front
    reflection read past genBSDF's stray first line; the other three blocks skipped."""
    from repo_paths import ROOT

    brdf = patina.load_brdf(f"{ROOT}/materials/radiance/blindsT3.xml")
    provenance = brdf.info()["provenance"]
    assert brdf.parametrization == "isotropic" and brdf.channel_kind == "mono"
    assert "TensorTree3, LBNL/Shirley-Chiu, reflection front" in provenance
    assert provenance.count("skipped") == 1 and "reflection back (Visible" in provenance
    values = brdf.table.values
    assert values.min() > 0.0 and np.isfinite(values).all()
