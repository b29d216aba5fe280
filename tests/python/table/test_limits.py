"""Issue 10, defect 13 (tables): memory in proportion to the file. validate evaluates in
bounded chunks whatever the channel count; an ASTM file cannot ask for more channels than
a table holds, nor a resampled grid beyond its stated size (docs/astm.md, docs/ptab.md)."""

from __future__ import annotations

import numpy as np
import pytest

import patina
from patina.errors import FormatError
from patina.table.formats import table_from_data
from patina.table.formats.astm import MAX_CHANNELS
from patina.table.formats.resample import MAX_GRID_VALUES
from patina.table.formats.tabledata import TableData
from patina.table.validation import VALUE_BUDGET, validate


def test_validate_of_a_4096_channel_table_evaluates_in_bounded_chunks():
    """A 147 KB .ptab of 4096 channels made validate take 6.4 GB: 40 000 pairs and 18 432
    albedo directions at once, times 4096 channels."""
    theta, phi = np.radians([0.0, 80.0]), np.radians([0.0, 180.0])
    values = np.full((2, 2, 2, 4096), 0.1)
    wavelengths = np.linspace(380, 780, 4096)
    brdf = patina.Brdf(
        table_from_data(TableData("isotropic", [theta, theta, phi], values, "spectral", wavelengths=wavelengths))
    )
    largest = 0
    evaluate = brdf.eval

    def recording(wi, wo, **kw):
        nonlocal largest
        out = evaluate(wi, wo, **kw)
        largest = max(largest, out.size)
        return out

    brdf.eval = recording  # type: ignore[method-assign]
    report = validate(brdf)
    assert report.ok, report.problems
    assert largest <= VALUE_BUDGET
    assert report.checks["reciprocity"]["pairs"] * 4096 <= VALUE_BUDGET


def astm(path, columns: int, rows: list[list[float]]) -> None:
    names = " ".join(f"{380 + 0.05 * i:.2f}" for i in range(columns))
    text = "#ASTM E1392-96\nVARS theta_i phi_i theta_s phi_s " + names + "\n"
    text += "\n".join(" ".join(f"{v:g}" for v in r[:4]) + (" 0.1" * columns) for r in rows) + "\n"
    path.write_text(text)


@pytest.mark.parametrize("columns", [MAX_CHANNELS + 1, 5000])
def test_an_astm_file_cannot_ask_for_more_channels_than_a_table_holds(tmp_path, columns):
    path = tmp_path / "wide.astm"
    astm(path, columns, [[0.1, 0, 0.2, 0.3]])
    with pytest.raises(FormatError) as e:
        patina.load_brdf(path)
    assert e.value.where == "line 2" and f"{columns} value columns" in e.value.problem


def test_a_resampled_grid_is_capped_before_it_is_made(tmp_path):
    rng = np.random.default_rng(0)
    rows = [[a, 0, b, c] for a, b, c in rng.uniform(0.1, 1.4, (40, 3))]
    path = tmp_path / "scattered.astm"
    astm(path, 600, rows)  # 40 distinct points: up to a 24 x 24 x 36 grid, times 600 channels
    with pytest.raises(FormatError) as e:
        patina.load_brdf(path)
    assert e.value.where == "grid" and f"more than the {MAX_GRID_VALUES}" in e.value.problem
