"""What an export starts from: fit.json, a ranking's best usable fit, a scene's material; and
damaged inputs end in FormatError, nothing else (hypothesis)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from export_helpers import GGX_FIT, WARD_FIT, write_json
from patina.errors import FormatError
from patina.export.source import load_source, sample_pairs


def test_fit_json_is_exact_and_evaluates_like_the_fit(tmp_path):
    source = load_source(write_json(tmp_path / "plastic.json", GGX_FIT))
    assert source.name == "plastic" and source.exact is not None
    assert source.exact.lobes[0].alpha == GGX_FIT["parameters"]["alpha"]
    wi, wo = sample_pairs(100)
    np.testing.assert_allclose(source.exact.eval(wi, wo), source.evaluate(wi, wo), rtol=1e-6)


def test_ward_fit_has_no_exact_form(tmp_path):
    assert load_source(write_json(tmp_path / "w.json", WARD_FIT)).exact is None


def _ranking(first_usable: bool) -> dict:
    ward = {**WARD_FIT, "usable": first_usable, "problems": [] if first_usable else ["flagged"]}
    ggx = {**GGX_FIT, "usable": True, "problems": []}
    return {**ward, "ranking": [ward, ggx]}


def test_ranking_gives_its_best_usable_fit(tmp_path):
    assert load_source(write_json(tmp_path / "r.json", _ranking(True))).model == "ward+lambert"
    assert load_source(write_json(tmp_path / "r2.json", _ranking(False))).model == "ggx+lambert"


def test_ranking_without_a_usable_fit_is_refused(tmp_path):
    doc = _ranking(False)
    doc["ranking"][1]["usable"] = False
    with pytest.raises(FormatError, match="no fit in the ranking is usable"):
        load_source(write_json(tmp_path / "r.json", doc))


def test_scene_material_by_name(tmp_path):
    fit = write_json(tmp_path / "fit.json", GGX_FIT)
    scene = {
        "version": 1,
        "camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "fov": 40, "width": 8, "height": 8},
        "materials": {
            "paint": {"type": "fit", "file": fit, "two_sided": True},
            "lacquer": {"type": "carpaint", "base": {"type": "lambert", "albedo": [0.5, 0.2, 0.1]}, "coat": {}},
        },
        "shapes": [{"type": "sphere", "material": "paint"}],
        "lights": [{"type": "point", "position": [0, 2, 2], "intensity": [1, 1, 1]}],
    }
    path = write_json(tmp_path / "scene.json", scene)
    paint = load_source(f"{path}#paint")
    assert paint.name == "paint" and paint.exact.two_sided
    lacquer = load_source(f"{path}#lacquer")
    assert lacquer.exact.coat is not None and lacquer.exact.lobes == ()
    with pytest.raises(FormatError, match="no such material"):
        load_source(f"{path}#nothing")


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_damaged_fit_files_raise_format_error_only(tmp_path, data):
    text = json.dumps(_ranking(False))
    cut = data.draw(st.integers(0, len(text)))
    junk = data.draw(st.text(max_size=8))
    damaged = text[:cut] + junk + text[cut + data.draw(st.integers(0, 8)) :]
    path = tmp_path / "f.json"
    path.write_text(damaged)
    try:
        source = load_source(str(path))
    except FormatError as e:
        assert str(path) in str(e)
        return
    wi, wo = sample_pairs(4)
    assert np.all(np.isfinite(source.evaluate(wi, wo)))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(
    entry=st.dictionaries(
        st.sampled_from(["model", "parameters", "usable"]),
        st.one_of(st.none(), st.booleans(), st.integers(), st.text(max_size=5), st.just({"alpha": 1})),
    )
)
def test_odd_ranking_entries_raise_format_error_only(tmp_path, entry):
    path = write_json(tmp_path / "r.json", {**GGX_FIT, "usable": False, "ranking": [entry]})
    try:
        load_source(path)
    except FormatError:
        pass


def test_a_measured_table_is_a_source_refitted_for_an_analytic_target(tmp_path):
    from patina.export import export
    from rgl_tables import MODEL, plastic_table

    path = str(tmp_path / "plastic.ptab")
    plastic_table().save(path)
    source = load_source(path)
    assert source.table is not None and source.exact is None and source.model == "table (ptab)"
    wi, wo = sample_pairs(200, seed=4)
    want = MODEL(wi, wo)
    assert np.median(np.abs(source.evaluate(wi, wo) - want) / want) < 0.01  # the table's interpolation
    report = export(path, "materialx", str(tmp_path / "plastic.mtlx"))
    assert report["refitted"] and report["measured_against"] == "the table's own samples"
    # a GGX plastic's table refitted to Lambert + GGX: close to exact
    assert report["error_against_source"]["relative_error_median"] < 0.01  # measured 0.0012
    assert report["error_against_source"]["ciede2000_mean"] < 0.2  # measured 0.03
