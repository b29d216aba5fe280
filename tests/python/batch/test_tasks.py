"""Issue 33: the batch's fit step recommends only a fit that passes the thresholds; when none
does it records none, and the least bad on top with its problems."""

from __future__ import annotations

import numpy as np

import patina
from patina.batch.library import Material, Settings
from patina.batch.tasks import _fit
from patina.synthetic.analytic import anisotropic_table, ward_anisotropic
from patina.table.formats import table_from_data


def brushed(tmp_path) -> Material:
    f = ward_anisotropic((0.05, 0.05, 0.06), (0.55, 0.56, 0.58), 0.35, 0.12)
    data = anisotropic_table(f, np.radians(np.linspace(0, 70, 8)), np.radians(np.arange(0, 360, 30.0)))
    path = tmp_path / "brushed.ptab"
    patina.Brdf(table_from_data(data)).save(str(path))
    return Material("brushed.ptab", str(path))


def test_isotropic_models_on_an_anisotropic_table_recommend_nothing(tmp_path):
    settings = Settings(models=("ggx+lambert", "ward+lambert"), starts=1)
    data, _ = _fit(brushed(tmp_path), settings, str(tmp_path), 0, False)
    assert data["recommended"] is None and not data["usable"]
    assert data["best_model"] in ("ggx+lambert", "ward+lambert")  # the least bad, shown
    assert any("isotropic model on an anisotropic table" in p for p in data["problems"])


def test_the_passing_fit_is_recommended_whatever_its_place_in_the_list(tmp_path):
    settings = Settings(models=("ward+lambert", "ward-aniso+lambert"), starts=1)
    data, _ = _fit(brushed(tmp_path), settings, str(tmp_path), 0, False)
    assert data["recommended"] == data["best_model"] == "ward-aniso+lambert" and data["usable"]
