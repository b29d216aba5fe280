"""Fitting: parameters of tables made from the model itself are recovered."""

from __future__ import annotations

import json

import numpy as np
import pytest

import patina
from fit_helpers import PHI, THETA, assert_recovered, model_table
from patina.cli import main
from patina.fitting import fit, table_samples
from patina.native import _core
from patina.synthetic.analytic import isotropic_grid
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData
from patina.table.spectral import xyz_to_linear_srgb

NAMES = ["rho_r", "rho_g", "rho_b", "alpha", "f0_r", "f0_g", "f0_b"]


CASES = [
    [0.3, 0.5, 0.2, 0.15, 0.04, 0.06, 0.08],
    [0.05, 0.05, 0.6, 0.35, 0.5, 0.3, 0.1],
    [0.6, 0.1, 0.1, 0.07, 0.04, 0.04, 0.04],
]


@pytest.mark.parametrize("params", CASES)
@pytest.mark.parametrize("loss", ["l2cos", "log"])
def test_noise_free_tables_are_recovered_within_2_percent(params, loss):
    r = fit(model_table(params), loss=loss, starts=2)
    assert r.converged, r.message
    got = np.array([r.parameters[n] for n in NAMES])
    np.testing.assert_allclose(got, params, rtol=0.02, atol=1e-3)
    assert r.metrics["loss_all_samples"] < 1e-8


@pytest.mark.parametrize("params", CASES[:2])
def test_two_percent_noise_recovers_within_5_percent(params):
    r = fit(model_table(params, noise=0.02, seed=3), loss="log", starts=2)
    got = np.array([r.parameters[n] for n in NAMES])
    np.testing.assert_allclose(got, params, rtol=0.05, atol=5e-3)


def test_samples_leave_out_grazing_and_missing_points():
    b = model_table(CASES[0])
    wi, wo, measured, weight = table_samples(b, max_theta_deg=60)
    assert np.all(wi[:, 2] > np.cos(np.radians(60)) - 1e-6) and np.all(wo[:, 2] > np.cos(np.radians(60)) - 1e-6)
    np.testing.assert_allclose(weight, wi[:, 2] * wo[:, 2], rtol=1e-6)
    assert measured.shape == wi.shape


def _with_channels(brdf: patina.Brdf, values: np.ndarray, kind: str) -> patina.Brdf:
    data = TableData("isotropic", [THETA, THETA, PHI], values, kind)
    return patina.Brdf(table_from_data(data), "", "test")


def test_monochrome_tables_are_fitted_as_grey():
    grey = [0.4, 0.4, 0.4, 0.2, 0.05, 0.05, 0.05]
    mono = _with_channels(model_table(grey), model_table(grey).values[..., :1], "mono")
    assert table_samples(mono)[2].shape[1] == 3
    r = fit(mono, starts=2)
    got = np.array([r.parameters[n] for n in NAMES])
    np.testing.assert_allclose(got, grey, rtol=0.02, atol=1e-3)


def test_xyz_tables_are_fitted_in_linear_srgb():
    rgb = model_table(CASES[0])
    xyz = _with_channels(rgb, rgb.values.astype(np.float64) @ np.linalg.inv(xyz_to_linear_srgb()).T, "xyz")
    np.testing.assert_allclose(table_samples(xyz)[2], table_samples(rgb)[2], rtol=1e-4, atol=1e-6)


def test_cli_writes_fit_json(tmp_path, capsys):
    table = tmp_path / "t.ptab"
    model_table(CASES[0]).save(table)
    out = tmp_path / "fit.json"
    assert main(["fit", str(table), "--out", str(out), "--starts", "1"]) == 0
    doc = json.loads(out.read_text())
    assert doc["model"] == "ggx+lambert" and doc["converged"]
    assert doc["table_checksum"].startswith("crc32:")
    assert abs(doc["parameters"]["alpha"] - 0.15) < 0.003
    assert main(["fit", str(table), "--model", "phong"]) == 2
    assert "unknown model" in capsys.readouterr().err
    assert main(["fit", str(table), "--starts", "0"]) == 2


@pytest.mark.parametrize("loss", ["l2cos", "log"])
def test_loss_matches_a_numpy_reference_at_every_width(loss):
    wi, wo, measured, weight = table_samples(model_table(CASES[1], noise=0.1, seed=5))
    params = CASES[0]
    f = _core.mixture_eval("ggx", params, wi, wo).astype(np.float64)
    w = weight.astype(np.float64)[:, None]
    m = measured.astype(np.float64)
    d = (f - m) * w if loss == "l2cos" else np.log1p(f * w) - np.log1p(m * w)
    want = float(np.mean(d * d))
    samples = _core.FitSamples(wi, wo, measured, weight)
    for width in [w for w in (1, 4, 8) if _core.width_supported(w)]:
        for threads in (1, 2):
            got = samples.mixture_loss("ggx", params, loss, width, threads)
            assert got == pytest.approx(want, rel=1e-4), (width, threads)


@pytest.mark.parametrize(
    "lobe, params, names",
    [
        (
            "beckmann",
            [0.2, 0.4, 0.6, 0.2, 0.05, 0.05, 0.05],
            ["rho_r", "rho_g", "rho_b", "alpha", "f0_r", "f0_g", "f0_b"],
        ),
        ("blinnphong", [0.5, 0.3, 0.1, 120.0, 0.04, 0.05, 0.06], ["rho_r", "rho_g", "rho_b", "exponent", *NAMES[4:]]),
        ("ward", [0.3, 0.3, 0.5, 0.12, 0.1, 0.08, 0.05], NAMES),
        ("ashikhmin", [0.4, 0.2, 0.2, 300.0, 0.05, 0.05, 0.05], ["rho_r", "rho_g", "rho_b", "exponent", *NAMES[4:]]),
    ],
)
def test_other_lobes_are_recovered(lobe, params, names):
    r = fit(model_table(params, lobe=lobe), model=f"{lobe}+lambert", starts=2)
    assert r.converged, r.message
    got = np.array([r.parameters[n] for n in names])
    np.testing.assert_allclose(got, params, rtol=0.02, atol=1e-3)


def test_two_lobes_fit_a_two_lobe_table():
    params = [0.2, 0.2, 0.2, 0.05, 0.04, 0.04, 0.04, 0.4, 0.3, 0.2, 0.1]
    r = fit(model_table(params), lobes=2, starts=3)
    assert r.model == "ggx+lambert x2"
    assert r.metrics["relative_error_p95"] < 0.05
    alphas = sorted([r.parameters["alpha_1"], r.parameters["alpha_2"]])
    np.testing.assert_allclose(alphas, [0.05, 0.4], rtol=0.05)


def test_compare_ranks_the_true_model_first_with_colour_differences(tmp_path, capsys):
    table = model_table([0.3, 0.2, 0.1, 0.1, 0.04, 0.05, 0.06], lobe="beckmann")
    from patina.fitting import compare

    results = compare(table, ["ggx+lambert", "beckmann+lambert", "blinnphong+lambert"], starts=1)
    assert results[0].model == "beckmann+lambert"
    assert results[0].metrics["ciede2000_mean"] < 0.05
    assert results[-1].metrics["ciede2000_mean"] > results[0].metrics["ciede2000_mean"]
    path = tmp_path / "t.ptab"
    table.save(path)
    # 1 if a model stops at its evaluation limit (a wrong model may), and the table says so
    assert main(["fit", str(path), "--compare", "ggx+lambert", "beckmann+lambert:1", "--starts", "1"]) in (0, 1)
    out = capsys.readouterr().out
    assert out.index("beckmann+lambert") < out.index("ggx+lambert ")
    assert main(["fit", str(path), "--compare", "ggx+lambert:x"]) == 2


def test_colour_differences_vanish_for_equal_colours():
    from patina.fitting import colour_differences

    rgb = np.random.default_rng(1).uniform(0, 0.3, (100, 3))
    cos_i = np.random.default_rng(2).uniform(0.1, 1, 100)
    assert np.allclose(colour_differences(rgb, rgb, cos_i), 0)
    shifted = colour_differences(rgb, rgb * np.array([1.1, 1.0, 1.0]), cos_i)
    assert np.median(shifted) > 0.5


COATED = [0.5, 0.1, 0.05, 0.3, 0.04, 0.04, 0.04, 0.04, 1.5]  # red base, rough lobe, coat alpha, eta
COATED_NAMES = [*NAMES, "coat_alpha", "coat_eta"]


@pytest.mark.parametrize("noise", [0.0, 0.02])
def test_a_coated_table_is_recovered_with_its_coat(noise):
    # the coat's index is held at 1.5 by default, and the base is identified given it
    r = fit(
        model_table(COATED, noise=noise, seed=3, lobe="ggx+coat"), coat=True, starts=3, loss="log" if noise else "l2cos"
    )
    assert r.model == "ggx+lambert+coat" and "coat_eta" not in r.at_bounds
    assert_recovered(r, COATED_NAMES, COATED, noise)


def test_a_coat_of_another_index_is_recovered_with_its_index_freed_or_given(tmp_path):
    params = [*COATED[:-1], 1.55]
    table = model_table(params, lobe="ggx+coat")
    r = fit(table, coat=True, fit_coat_eta=True, starts=3)
    np.testing.assert_allclose([r.parameters[n] for n in COATED_NAMES], params, rtol=0.02, atol=1e-3)
    path = tmp_path / "coated.ptab"
    table.save(path)
    out = tmp_path / "fit.json"
    assert main(["fit", str(path), "--coat", "--coat-eta", "1.55", "--starts", "2", "--out", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["parameters"]["coat_eta"] == pytest.approx(1.55)
    np.testing.assert_allclose([doc["parameters"][n] for n in COATED_NAMES], params, rtol=0.02, atol=1e-3)


def test_per_channel_shapes_are_recovered(tmp_path):
    # alpha r g b differ: 0.08, 0.15, 0.3
    params = [0.3, 0.2, 0.1, 0.08, 0.15, 0.3, 0.04, 0.05, 0.06]
    wi, wo = isotropic_grid(THETA, THETA, PHI)
    values = _core.mixture_eval("ggx", params, wi.astype(np.float32), wo.astype(np.float32), 0, True)
    table = patina.Brdf(
        table_from_data(TableData("isotropic", [THETA, THETA, PHI], values.reshape(26, 26, 48, 3), "rgb")), "", "t"
    )
    r = fit(table, per_channel=True, starts=2)
    got = [r.parameters[n] for n in ("alpha_r", "alpha_g", "alpha_b")]
    np.testing.assert_allclose(got, [0.08, 0.15, 0.3], rtol=0.02)
    out = tmp_path / "fit.json"
    from patina.fitting import read_fit, write_fit

    write_fit(r, str(out))
    np.testing.assert_allclose(read_fit(str(out)).eval(wi[:50], wo[:50]), values[:50], rtol=0.02, atol=1e-4)
