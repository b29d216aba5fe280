"""LBNL WINDOW / Radiance BSDF XML (python/patina/table/formats/window_xml.py): Klems
documents written here from the format's definition, read back exactly at the patch
centres, front or back, XYZ or single-channel; transmission skipped or refused; bad
documents one line naming the place; random damage fuzzed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patina
from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.angles import angles_to_directions
from patina.table.formats.window_xml import read_window_xml
from reader_fuzz import load_damaged

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)
KLEMS_FULL = [(0, 0, 5, 1), (10, 5, 15, 8), (20, 15, 25, 16), (30, 25, 35, 20), (40, 35, 45, 24), (50, 45, 55, 24),
              (60, 55, 65, 24), (70, 65, 75, 16), (82.5, 75, 90, 12)]  # fmt: skip


def patch_centres(rings=KLEMS_FULL) -> tuple[np.ndarray, np.ndarray]:
    theta = np.concatenate([[t] * n for t, _, _, n in rings])
    phi = np.concatenate([np.arange(n) * 360.0 / n for *_, n in rings])
    return theta, phi


def klems_matrix(channel: int, scale: float = 1.0) -> np.ndarray:
    """[outgoing, incident]: MODEL at the patch centres, the outgoing basis mirrored."""
    theta, phi = patch_centres()
    wi = angles_to_directions(np.radians(theta), np.radians(phi))
    wo = angles_to_directions(np.radians(theta), np.radians(phi + 180.0))
    n = theta.size
    pairs_i = np.repeat(wi[None], n, axis=0).reshape(-1, 3)
    pairs_o = np.repeat(wo[:, None], n, axis=1).reshape(-1, 3)
    return scale * MODEL(pairs_i, pairs_o)[:, channel].reshape(n, n)


def window_xml(blocks: list[tuple[str, str, str, np.ndarray]], stray: str = "", structure: str = "Columns") -> str:
    """A WindowElement document; blocks: (direction, wavelength label, detector, [out, in] matrix)."""
    basis = "".join(
        f"<AngleBasisBlock><Theta>{t}</Theta><nPhis>{n}</nPhis><ThetaBounds><LowerTheta>{lo}</LowerTheta>"
        f"<UpperTheta>{hi}</UpperTheta></ThetaBounds></AngleBasisBlock>"
        for t, lo, hi, n in KLEMS_FULL
    )
    data = ""
    for direction, label, detector, matrix in blocks:
        m = matrix if structure == "Columns" else matrix.T
        numbers = ",\n".join(", ".join(f"{v:.9g}" for v in row) for row in m)
        data += (
            f"<WavelengthData><LayerNumber>System</LayerNumber><Wavelength unit='Integral'>{label}</Wavelength>"
            f"<DetectorSpectrum>{detector}</DetectorSpectrum><WavelengthDataBlock>"
            f"<WavelengthDataDirection>{direction}</WavelengthDataDirection>"
            "<ColumnAngleBasis>LBNL/Klems Full</ColumnAngleBasis><RowAngleBasis>LBNL/Klems Full</RowAngleBasis>"
            f"<ScatteringDataType>BRDF</ScatteringDataType><ScatteringData>{numbers}</ScatteringData>"
            "</WavelengthDataBlock></WavelengthData>"
        )
    return (
        f"{stray}<?xml version='1.0' encoding='UTF-8'?>\n<WindowElement xmlns='http://windows.lbl.gov'>"
        "<WindowElementType>System</WindowElementType><Optical><Layer><Material><Name>test</Name></Material>"
        f"<DataDefinition><IncidentDataStructure>{structure}</IncidentDataStructure><AngleBasis>"
        f"<AngleBasisName>LBNL/Klems Full</AngleBasisName>{basis}</AngleBasis></DataDefinition>"
        f"{data}</Layer></Optical></WindowElement>\n"
    )


def _write(tmp_path, text: str, name: str = "w.xml") -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def _at_patch_centres(brdf) -> tuple[np.ndarray, np.ndarray]:
    theta, phi = patch_centres()
    pick = theta < 80  # the last ring's centre (82.5) lies on the grid too, but keep clear of the horizon
    t, p = np.radians(theta[pick]), np.radians(phi[pick])
    i, o = np.meshgrid(np.arange(t.size), np.arange(t.size), indexing="ij")
    got = brdf.eval_angles(t[i], p[i], t[o], p[o] + math.pi)
    return got, (i, o, pick)


@pytest.mark.parametrize("structure", ["Columns", "Rows"])
def test_xyz_read_back_exactly_at_the_patch_centres(tmp_path, structure):
    blocks = [("Reflection Front", "CIE-" + k, f"ASTM E308 1931 {k}.dsp", klems_matrix(c)) for c, k in enumerate("XYZ")]
    blocks.append(("Transmission Front", "Visible", "", klems_matrix(1, 0.2)))
    brdf = patina.load_brdf(_write(tmp_path, window_xml(blocks, structure=structure)))
    assert brdf.channel_kind == "xyz" and brdf.source_format == "window_xml"
    got, (i, o, pick) = _at_patch_centres(brdf)
    want = np.stack([klems_matrix(c)[np.ix_(pick, pick)].T[i, o] for c in range(3)], axis=-1)
    assert np.allclose(got, want, rtol=1e-5)
    provenance = brdf.info()["provenance"]
    assert "LBNL/Klems Full, 145 patches, reflection front, xyz" in provenance
    assert "skipped: transmission front (Visible)" in provenance


def test_back_side_and_stray_line(tmp_path):
    text = window_xml(
        [
            ("Reflection Front", "Visible", "", klems_matrix(1)),
            ("Reflection Back", "Visible", "", klems_matrix(1, 0.5)),
        ],
        stray="written by a tool\n",
    )
    path = _write(tmp_path, text)
    front = patina.load_brdf(path)
    back = patina.Brdf(patina.table.formats.table_from_data(read_window_xml(path, side="back")))
    assert front.channel_kind == "mono"
    assert np.allclose(_at_patch_centres(back)[0], 0.5 * _at_patch_centres(front)[0], rtol=1e-5)


@pytest.mark.parametrize(
    "text, where, problem",
    [
        ("<?xml version='1.0'?><Other/>", "root element", "expected <WindowElement>"),
        ("<?xml version='1.0'?>\n<WindowElement>\n<Optical>", "line 3", "not well-formed XML"),
        ("just words", "line 1", "no XML element"),
    ],
)
def test_not_a_bsdf_document(tmp_path, text, where, problem):
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, text))
    assert e.value.where.startswith(where) and problem in e.value.problem


def test_transmission_only_wrong_count_and_a_klems_block_in_a_tree_document(tmp_path):
    with pytest.raises(FormatError, match="Patina tables are reflection"):
        patina.load_brdf(_write(tmp_path, window_xml([("Transmission Front", "Visible", "", klems_matrix(1))])))
    short = window_xml([("Reflection Front", "Visible", "", klems_matrix(1)[:, :100])])
    with pytest.raises(FormatError) as e:
        patina.load_brdf(_write(tmp_path, short))
    assert "ScatteringData" in e.value.where and "14500 values: expected 145 x 145" in e.value.problem
    tree = window_xml([("Reflection Front", "Visible", "", klems_matrix(1))]).replace("Columns", "TensorTree3")
    with pytest.raises(FormatError, match=r"block 1 AngleBasis\): '': a tensor tree needs LBNL/Shirley-Chiu"):
        patina.load_brdf(_write(tmp_path, tree))


SMALL = window_xml([("Reflection Front", "Visible", "", np.round(klems_matrix(1), 2))]).encode()
FUZZ = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(at=st.integers(min_value=0, max_value=len(SMALL) - 1), value=st.integers(0, 255), cut=st.booleans())
def test_damaged_documents_raise_one_format_error(at, value, cut):
    load_damaged(SMALL, at, value, cut, "f.xml", patina.load_brdf)


def test_bundled_real_klems_file(capsys):
    """materials/radiance/klems_aniso_high.xml (LBNL frads' test resources): its front reflection."""
    from repo_paths import ROOT

    brdf = patina.load_brdf(f"{ROOT}/materials/radiance/klems_aniso_high.xml")
    info = brdf.info()
    assert info["format"] == "window_xml" and brdf.channel_kind == "mono"
    assert "LBNL/Klems Full, 145 patches, reflection front" in info["provenance"]
    assert "skipped: transmission front" in info["provenance"]
    assert 0.03 < info["value_min"][0] < info["value_max"][0] < 2.5  # a fabric shade: 1/sr, no spike
