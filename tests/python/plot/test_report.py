"""`patina plot` and fit.json: the report's page (labels, tables, captions), several fits side by side,
the one slice plotter with its legend and mirror line, the polar plots' radial scale, bad fit files."""

from __future__ import annotations

import json
import os
import re

import numpy as np
import pytest

import patina
import patina.plot.polar as polar
import patina.plot.report as report
import patina.plot.slices as slices
from patina.cli import main
from patina.fitting import FitResult, read_fit
from patina.fitting.fit_file import write_ranking
from patina.plot.fits import read_all_fits
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData

# The bundled red plastic's own model (its provenance): a fit that matches it.
GGX = {"rho_r": 0.55, "rho_g": 0.08, "rho_b": 0.05, "alpha": 0.2, "f0_r": 0.04, "f0_g": 0.04, "f0_b": 0.04}
BECKMANN = {**GGX, "alpha": 0.22, "f0_r": 0.036, "f0_g": 0.036, "f0_b": 0.036}
METRICS = {
    "loss_all_samples": 1.8e-8,
    "rmse": 0.0026,
    "relative_error_median": 0.0017,
    "relative_error_p95": 0.0066,
    "ciede2000_mean": 0.033,
    "ciede2000_p95": 0.064,
}


def _result(model: str, parameters: dict[str, float], scale: float, **extra) -> FitResult:
    metrics = {k: v * scale for k, v in METRICS.items()}
    metrics["loss"] = metrics["loss_all_samples"]  # as fit --compare writes it: the loss on the samples fitted
    loss = metrics["loss_all_samples"]
    return FitResult(model, parameters, "l2cos", loss, metrics, True, "converged", 1.0, 100, **extra)


@pytest.fixture(scope="module")
def fit_files(tmp_path_factory, bundled_ptab) -> dict[str, str]:
    """One fit.json, and a ranking as `patina fit --compare --out` writes it (the second fit flagged)."""
    d = tmp_path_factory.mktemp("fits")
    one = d / "ggx.json"
    one.write_text(json.dumps(_result("ggx+lambert", GGX, 1.0, source=bundled_ptab).as_json()))
    ranking = d / "ranking.json"
    results = [
        _result("ggx+lambert", GGX, 1.0, source=bundled_ptab),
        _result("beckmann+lambert", BECKMANN, 40.0, source=bundled_ptab, at_bounds=["f0_r"]),
    ]
    write_ranking(results, str(ranking))
    return {"one": str(one), "ranking": str(ranking)}


@pytest.fixture(scope="module")
def ranked_report(tmp_path_factory, bundled_ptab, fit_files) -> str:
    out = tmp_path_factory.mktemp("report") / "r"
    assert main(["plot", bundled_ptab, "--fit", fit_files["ranking"], "--out", str(out), "--no-3d"]) == 0
    return str(out)


def test_plot_with_a_fit_writes_the_report(tmp_path, bundled_ptab):
    fit_json = tmp_path / "fit.json"
    assert main(["fit", bundled_ptab, "--out", str(fit_json), "--starts", "1"]) == 0
    out = tmp_path / "report"
    assert main(["plot", bundled_ptab, "--fit", str(fit_json), "--out", str(out)]) == 0
    for name in ("index.html", "slices.png", "polar.png", "lobe3d.png", "validate.json"):
        assert (out / name).stat().st_size > 0
    assert (out / "slices.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    page = (out / "index.html").read_text()
    assert "<h2>Fit</h2>" in page and "<th>ggx+lambert</th>" in page and "Clean: every check passed." in page
    assert '<img src="lobe3d.png"' in page and "bottom row: the fit" in page
    assert json.loads((out / "validate.json").read_text())["ok"] is True
    assert not list(out.glob("*.tmp*"))


def test_the_page_names_metrics_and_parameters_for_a_reader(ranked_report):
    page = open(os.path.join(ranked_report, "index.html"), encoding="utf-8").read()
    for label in ("CIEDE2000 mean", "CIEDE2000, 95th percentile", "relative error, median", "RMS error of f (1/sr)"):
        assert f'<th scope="row">{label}' in page
    for raw in METRICS:  # the JSON keys are not what a reader sees
        assert raw not in page
    assert page.count('<th scope="row">loss on the samples fitted<') == 1  # one row a metric
    assert "diffuse albedo \N{GREEK SMALL LETTER RHO}, red" in page and "<code>rho_r</code>" in page
    assert "0.17 %" in page  # relative error as a percentage
    # Validation as a table of checks, each with its status
    assert re.search(r"<td>reciprocity</td>\s*<td class=\"status ok\">ok</td>", page)
    # Every figure has a caption; the stylesheet is inlined and keeps images within the page
    assert page.count("<img ") == page.count("<figcaption>") == 2
    assert "max-width: 100%" in page and '<meta name="viewport"' in page
    assert "The 3-D lobe view was skipped: not requested (--no-3d)." in page


def test_a_ranking_shows_every_fit_side_by_side(ranked_report):
    page = open(os.path.join(ranked_report, "index.html"), encoding="utf-8").read()
    assert "Fits, side by side" in page
    head = re.search(r"<th>metric</th>(.*?)</tr>", page, re.S).group(1)
    assert head.index("ggx+lambert") < head.index("beckmann+lambert")  # in the ranking's order
    # Each metric row has one cell per fit, the best shaded; a parameter at its bound is flagged
    row = re.search(r"CIEDE2000 mean \(ΔE00\)</th>(.*?)</tr>", page).group(1)
    assert row.count("<td") == 2 and 'class="num best">0.03<' in row and ">1.32<" in row
    assert "at a bound: specular reflectance F0, red" in page and "(at bound)" in page


def test_fit_files_and_rankings_combine_and_same_models_are_told_apart(fit_files):
    fits = read_all_fits([fit_files["one"], fit_files["ranking"]])
    names = [f.name for f in fits]
    assert names == ["ggx+lambert (ggx.json)", "ggx+lambert (ranking.json)", "beckmann+lambert"]


def _capture(monkeypatch, module):
    """The matplotlib figure a plot function would save (save_figure closes it)."""
    figures = []
    monkeypatch.setattr(module, "save_figure", lambda fig, path: figures.append(fig))
    return figures


def test_the_slice_plot_overlays_each_fit_with_a_legend_and_the_mirror_line(monkeypatch, bundled_ptab, fit_files):
    brdf = patina.load_brdf(bundled_ptab)
    fits = [(f.name, f.model) for f in read_all_fits([fit_files["ranking"]])]
    figures = _capture(monkeypatch, slices)
    caption = slices.plot_inplane_slices(brdf, "unused.png", (0, 45), fits=fits)
    (fig,) = figures
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    fit_names = ["fit: ggx+lambert", "fit: beckmann+lambert"]
    assert legend == ["R", "G", "B", "measured", *fit_names, "mirror direction (θo = θi)"]
    ax = fig.axes[1]
    mirror = [line for line in ax.get_lines() if list(line.get_xdata()) == [45, 45]]
    assert len(mirror) == 1, "the mirror direction theta_o = theta_i is drawn"
    curves = [line for line in ax.get_lines() if line not in mirror]
    assert len(curves) == 3 * 3  # three channels: measured and each fit
    # measured solid, each fit its own style, in every channel's colour
    assert {line.get_linestyle() for line in curves} == {"-", "--", ":"}
    assert len({line.get_color() for line in curves}) == 3
    assert "mirror direction" in caption and "line style" in caption


def test_one_slice_plotter_serves_the_report_and_patina_slices():
    assert report.plot_inplane_slices is slices.plot_inplane_slices
    assert not hasattr(report, "plot_slices")


def test_polar_plots_have_a_labelled_log_radius_and_a_legend(monkeypatch, bundled_ptab, fit_files):
    brdf = patina.load_brdf(bundled_ptab)
    fits = [(f.name, f.model) for f in read_all_fits([fit_files["one"]])]
    figures = _capture(monkeypatch, polar)
    caption = polar.plot_incidence_polar(brdf, "unused.png", (0, 30, 60), fits=fits)
    (fig,) = figures
    visible = [ax for ax in fig.axes if ax.get_visible()]
    assert len(visible) == 3
    for ax in visible:
        labels = [t.get_text() for t in ax.get_yticklabels()]
        assert len(labels) >= 2 and all(re.fullmatch(r"\$10\^\{-?\d+\}\$", s) for s in labels)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["measured", "fit: ggx+lambert", "mirror direction"]
    assert "1/sr" in fig._suptitle.get_text() and "log radius" in fig._suptitle.get_text()
    assert "logarithmic" in caption and "1/sr" in caption


def test_the_template_is_installed_with_the_package():
    templates = os.path.join(os.path.dirname(report.__file__), "templates")
    assert os.path.isfile(os.path.join(templates, "report.html.j2"))
    assert os.path.isfile(os.path.join(templates, "report.css"))


def test_fitted_model_evaluates_like_the_fit(tmp_path, bundled_ptab, fit_files):
    model = read_fit(fit_files["one"])
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


@pytest.mark.parametrize(
    "doc, place",
    [
        ({"ranking": [{"model": "ggx+lambert", "parameters": GGX}, {"model": "ggx+lambert"}]}, "ranking[1].parameters"),
        ([{"model": "ggx+lambert", "parameters": GGX}, 3], "[1]"),
        ({"ranking": []}, "holds no fits"),
        ({"model": "ggx+lambert", "parameters": {**GGX, "alpha": 10**401}}, "parameters"),
    ],
)
def test_bad_rankings_name_the_entry_and_nothing_is_drawn(tmp_path, bundled_ptab, capsys, doc, place):
    bad = tmp_path / "ranking.json"
    bad.write_text(json.dumps(doc))
    out = tmp_path / "r"
    assert main(["plot", bundled_ptab, "--fit", str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and place in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not out.exists()  # refused before any figure


def test_a_spectral_table_gets_its_report_without_fits_drawn_over_single_wavelengths(tmp_path, fit_files):
    axes = [np.linspace(0, 1.5, 8), np.linspace(0, 1.5, 9), np.linspace(0, np.pi, 7)]
    wavelengths = np.arange(400.0, 701.0, 50.0)
    values = np.broadcast_to(np.linspace(0.1, 0.3, wavelengths.size), (8, 9, 7, wavelengths.size)).astype(np.float32)
    data = TableData("isotropic", axes, values, "spectral", wavelengths=wavelengths, provenance="test")
    brdf = patina.Brdf(table_from_data(data), str(tmp_path / "flat.ptab"), "ptab")
    out = tmp_path / "r"
    report.write_report(brdf, str(out), read_all_fits([fit_files["one"]]), lobes=None)
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "fits are not overlaid because a spectral table" in page
    assert "mean of the wavelengths" in page and "The fits are not drawn" in page
    assert "<h2>Fit</h2>" in page  # its parameters and metrics are still listed


def test_what_a_fit_file_holds_besides_its_model_is_shown_only_where_well_formed(tmp_path, bundled_ptab):
    odd = tmp_path / "odd.json"
    doc = {"model": "ggx+lambert", "parameters": GGX, "metrics": [1], "at_bounds": "alpha", "source": 3}
    odd.write_text(json.dumps(doc))
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"model": "ggx+lambert", "parameters": GGX, "source": "elsewhere/paint.ptab"}))
    out = tmp_path / "r"
    assert main(["plot", bundled_ptab, "--fit", str(odd), str(other), "--out", str(out), "--no-3d"]) == 0
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "fitted to paint.ptab, not to this table" in page


def test_an_unusable_output_directory_is_refused_before_any_work(tmp_path, bundled_ptab, capsys):
    taken = tmp_path / "taken"
    taken.write_text("a file, not a directory")
    assert main(["plot", bundled_ptab, "--out", str(taken), "--no-3d"]) == 2
    err = capsys.readouterr().err
    assert f"--out {taken}: cannot make the report directory" in err and "report:" not in err
