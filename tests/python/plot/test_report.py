"""`patina plot` and fit.json: figures, index.html, and clear errors for bad fit files."""

from __future__ import annotations

import json

import pytest

import patina
from patina.cli import main
from patina.fitting import read_fit


def test_plot_with_a_fit_writes_the_report(tmp_path, bundled_ptab):
    fit_json = tmp_path / "fit.json"
    assert main(["fit", bundled_ptab, "--out", str(fit_json), "--starts", "1"]) == 0
    out = tmp_path / "report"
    assert main(["plot", bundled_ptab, "--fit", str(fit_json), "--out", str(out)]) == 0
    for name in ("index.html", "slices.png", "polar.png", "lobe3d.png", "validate.json"):
        assert (out / name).stat().st_size > 0
    assert (out / "slices.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    page = (out / "index.html").read_text()
    assert "Fit: ggx+lambert" in page and "slices.png" in page and "clean" in page
    assert '<img src="lobe3d.png">' in page and "bottom row: the fit" in page
    assert json.loads((out / "validate.json").read_text())["ok"] is True
    assert not list(out.glob("*.tmp*"))


def test_fitted_model_evaluates_like_the_fit(tmp_path, bundled_ptab):
    fit_json = tmp_path / "fit.json"
    main(["fit", bundled_ptab, "--out", str(fit_json), "--starts", "1"])
    model = read_fit(str(fit_json))
    import numpy as np

    wi = np.array([[0.0, 0.0, 1.0]], np.float32)
    wo = np.array([[0.5, 0.0, 0.8660254]], np.float32)
    measured = patina.load_brdf(bundled_ptab).eval(wi, wo)
    np.testing.assert_allclose(model.eval(wi, wo), measured, rtol=0.05)


@pytest.mark.parametrize(
    "content, message",
    [
        ("{not json", "not JSON"),
        ("[1, 2]", "JSON object"),
        ('{"model": "ggx+lambert"}', "parameters"),
        ('{"model": "phong+lambert+", "parameters": {}}', "unknown model"),
        ('{"model": "ggx+lambert", "parameters": {"rho_r": 1}}', "missing"),
        (
            '{"model": "ggx+lambert", "parameters": {"rho_r": "x", "rho_g": 0, "rho_b": 0, "alpha": 0.1, '
            '"f0_r": 0, "f0_g": 0, "f0_b": 0}}',
            "parameters",
        ),
    ],
)
def test_bad_fit_files_are_refused_clearly(tmp_path, bundled_ptab, capsys, content, message):
    bad = tmp_path / "fit.json"
    bad.write_text(content)
    with pytest.raises(patina.FormatError, match=message):
        read_fit(str(bad))
    assert main(["plot", bundled_ptab, "--fit", str(bad), "--out", str(tmp_path / "r")]) == 2
    assert str(bad) in capsys.readouterr().err
