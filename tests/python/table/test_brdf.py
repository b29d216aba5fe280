"""The Python API: load_brdf, eval, eval_angles, width, save, info."""

from __future__ import annotations

import numpy as np
import pytest

import patina
from conftest import WIDTHS
from patina.table.brdf import angles_to_directions
from reference import evaluate, hemisphere


def test_eval_shapes_and_widths_agree_bit_for_bit(bundled_ptab):
    brdf = patina.load_brdf(bundled_ptab)
    wi, wo = hemisphere(10007, 1, below=0.05), hemisphere(10007, 2, below=0.05)
    results = {w: brdf.eval(wi, wo, width=w) for w in WIDTHS}
    assert results[1].shape == (10007, 3) and results[1].dtype == np.float32
    for w in WIDTHS:
        np.testing.assert_array_equal(results[w], results[1])
    assert np.all(results[1][(wi[:, 2] <= 0) | (wo[:, 2] <= 0)] == 0)
    np.testing.assert_array_equal(brdf.eval(wi, wo), results[1])  # default width


def test_eval_matches_double_precision_reference(bundled_ptab):
    brdf = patina.load_brdf(bundled_ptab)
    wi, wo = hemisphere(20000, 3), hemisphere(20000, 4)
    got = brdf.eval(wi, wo, width=1)
    want = evaluate(brdf, wi, wo)
    rel = np.abs(got - want) / np.maximum(np.abs(want), 1e-3)
    assert rel.max() < 1e-4, rel.max()


def test_eval_angles_agrees_with_eval(bundled_ptab):
    brdf = patina.load_brdf(bundled_ptab)
    rng = np.random.default_rng(5)
    ti, to = rng.uniform(0, 1.5, 500), rng.uniform(0, 1.5, 500)
    pi, po = rng.uniform(0, 2 * np.pi, 500), rng.uniform(0, 2 * np.pi, 500)
    by_angles = brdf.eval_angles(ti, pi, to, po)
    by_vectors = brdf.eval(angles_to_directions(ti, pi), angles_to_directions(to, po))
    np.testing.assert_array_equal(by_angles, by_vectors)
    grid = brdf.eval_angles(0.3, 0.0, np.linspace(0, 1.4, 7)[:, None], np.array([0.0, np.pi]))
    assert grid.shape == (7, 2, 3)


def test_knots_are_reproduced(bundled_ptab):
    brdf = patina.load_brdf(bundled_ptab)
    ti_axis, to_axis, pd_axis = brdf.axes
    values = brdf.values
    i, j, k = np.meshgrid([3, 10, 20], [2, 15, 25], [5, 30, 58], indexing="ij")
    got = brdf.eval_angles(ti_axis[i], 0.0, to_axis[j], pd_axis[k])
    np.testing.assert_allclose(got, values[i, j, k], rtol=5e-5)


def test_save_round_trip_and_info(bundled_astm, tmp_path):
    brdf = patina.load_brdf(bundled_astm)
    out = tmp_path / "copy.ptab"
    brdf.save(out)
    again = patina.load_brdf(out)
    np.testing.assert_array_equal(again.values, brdf.values)
    for a, b in zip(again.axes, brdf.axes):
        np.testing.assert_array_equal(a, b)
    info = again.info()
    assert info["parametrization"] == "isotropic"
    assert info["channels"] == 3 and info["channel_kind"] == "rgb"
    assert [a["knots"] for a in info["axes"]] == [10, 10, 19]
    assert "ASTM" in info["provenance"]
    assert not list(tmp_path.glob("*.tmp*")), "temporary files left behind"


def test_bad_arguments_are_clear(bundled_ptab, tmp_path):
    brdf = patina.load_brdf(bundled_ptab)
    with pytest.raises(ValueError, match=r"shape \(n, 3\)"):
        brdf.eval(np.zeros((4, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match="rows"):
        brdf.eval(np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(ValueError, match="width"):
        brdf.eval(np.zeros((4, 3)), np.zeros((4, 3)), width=3)
    with pytest.raises(ValueError, match=r"\.ptab"):
        brdf.save(tmp_path / "x.binary")
    with pytest.raises(patina.FormatError, match="cannot open"):
        patina.load_brdf(tmp_path / "missing.ptab")
    with pytest.raises(patina.FormatError, match="directory"):
        patina.load_brdf(tmp_path)
    junk = tmp_path / "junk.xyz"
    junk.write_bytes(b"\x00\x01garbage")
    with pytest.raises(patina.FormatError, match="unrecognised"):
        patina.load_brdf(junk)


def test_nan_directions_give_zero_not_garbage(bundled_ptab):
    brdf = patina.load_brdf(bundled_ptab)
    wi = np.array([[np.nan, 0, 1], [0, 0, np.nan]], np.float32)
    wo = np.array([[0, 0, 1], [0, 0, 1]], np.float32)
    for w in WIDTHS:
        assert np.all(np.isfinite(brdf.eval(wi, wo, width=w)))


def test_spectral_and_masked_tables_from_arrays():
    from patina.table.formats import table_from_data
    from patina.table.formats.tabledata import TableData

    axes = [np.linspace(0, 1.5, 4), np.linspace(0, 1.5, 5), np.linspace(0, np.pi, 6)]
    values = np.random.default_rng(0).uniform(0.1, 1, (4, 5, 6, 7)).astype(np.float32)
    mask = np.ones((4, 5, 6), bool)
    mask[1, 2, 3] = False
    data = TableData("isotropic", axes, values, "spectral", wavelengths=np.linspace(400, 700, 7), mask=mask)
    brdf = patina.Brdf(table_from_data(data))
    assert brdf.channels == 7 and brdf.table.missing_count == 1
    np.testing.assert_allclose(brdf.wavelengths, np.linspace(400, 700, 7))
    wi, wo = hemisphere(3000, 7), hemisphere(3000, 8)
    np.testing.assert_allclose(brdf.eval(wi, wo), evaluate(brdf, wi, wo), rtol=2e-4, atol=1e-5)
    bad = TableData("isotropic", axes, values[:, :, :5], "spectral", wavelengths=np.linspace(400, 700, 7))
    with pytest.raises(ValueError):
        table_from_data(bad)


def test_save_to_a_name_that_is_not_utf8(tmp_path, bundled_ptab):
    """The engine's writer takes UTF-8 names: save writes a UTF-8 temporary beside the target
    (through an alias of a folder whose own name is not UTF-8) and renames it."""
    import os

    folder = os.fsencode(tmp_path) + b"/d\xe9"
    os.mkdir(folder)
    target = os.fsdecode(folder + b"/t\xff.ptab")
    brdf = patina.load_brdf(bundled_ptab)
    brdf.save(target)
    brdf.save(target)  # replaced, as any output
    assert os.listdir(folder) == [b"t\xff.ptab"]
    assert np.array_equal(patina.load_brdf(target).table.values, brdf.table.values)
    with pytest.raises(OSError, match=r"d\\xe9/nowhere/t\\xff.ptab: cannot write"):
        brdf.save(os.fsdecode(folder + b"/nowhere/t\xff.ptab"))
