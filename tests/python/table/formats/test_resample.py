"""Scattered ASTM measurements are resampled onto an irregular grid, with the error reported."""

from __future__ import annotations

import numpy as np
import pytest

import patina
from patina.synthetic.analytic import plastic
from patina.table.brdf import angles_to_directions
from patina.table.formats.astm import read_astm

MODEL = plastic(diffuse=(0.4, 0.3, 0.2), specular=0.04, roughness=0.35)


def scattered_file(path, n: int = 6000, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    ti, to = rng.uniform(0, np.radians(80), n), rng.uniform(0, np.radians(80), n)
    pd = rng.uniform(0, np.pi, n)
    rgb = MODEL(angles_to_directions(ti, 0 * ti), angles_to_directions(to, pd))
    lines = ["#ASTM E1392-96", "SOURCE scattered test", f"NUM_POINTS {n}", "VARS theta_i phi_i theta_s phi_s R G B"]
    lines += [f"{a:.7g} 0 {b:.7g} {c:.7g} {v[0]:.7g} {v[1]:.7g} {v[2]:.7g}" for a, b, c, v in zip(ti, to, pd, rgb)]
    path.write_text("\n".join(lines) + "\n")


def test_scattered_data_is_resampled_and_the_error_reported(tmp_path):
    path = tmp_path / "scattered.astm"
    scattered_file(path)
    with pytest.raises(patina.FormatError, match="not on a tensor grid"):
        read_astm(path)  # the strict reader
    brdf = patina.load_brdf(path)
    info = brdf.info()
    assert [a["knots"] for a in info["axes"]] == [24, 24, 36]
    assert "resampled from 6000 scattered points" in info["provenance"]
    assert "relative error at the measured points" in info["provenance"]
    # against the model the data came from, inside the measured range
    rng = np.random.default_rng(1)
    ti, to, pd = rng.uniform(0.05, 1.3, 3000), rng.uniform(0.05, 1.3, 3000), rng.uniform(0, np.pi, 3000)
    wi, wo = angles_to_directions(ti, 0 * ti), angles_to_directions(to, pd)
    got = brdf.eval(wi, wo).astype(np.float64)
    want = MODEL(wi, wo)
    rel = np.abs(got - want) / want
    assert np.median(rel) < 0.05, np.median(rel)
    assert np.all(np.isfinite(got))


def test_knots_follow_the_data_density():
    from patina.table.formats.resample import choose_knots

    x = np.concatenate([np.linspace(0, 0.1, 900), np.linspace(0.1, 1.5, 100)])
    knots = choose_knots(x, 20)
    assert knots.size == 20 and knots[0] == 0 and knots[-1] == 1.5
    assert np.sum(knots < 0.1) > 10  # dense where the data are
    assert np.array_equal(choose_knots(np.array([0.0, 0.5, 0.5, 1.0]), 20), [0.0, 0.5, 1.0])


def test_angles_a_rounding_error_apart_are_one_knot():
    """20 deg and 20 deg + 1e-14 (a Zemax file's directions turned into angles) are one knot:
    as two, float32 tables saw them equal and refused the axis."""
    from patina.table.formats.resample import choose_knots

    x = np.radians([0.0, 20.0, 40.0])
    knots = choose_knots(np.concatenate([x, x + 1e-14, [x[1] + 1e-9]]), 20)
    assert np.array_equal(knots, x) and np.all(np.diff(knots.astype(np.float32)) > 0)


def test_csv_grid_and_scattered_and_bad(tmp_path):
    rng = np.random.default_rng(3)
    grid = tmp_path / "grid.csv"
    rows = ["theta_i,phi_i,theta_o,phi_o,R,G,B"]
    for a in (0.0, 0.4, 0.8):
        for b in (0.0, 0.5, 1.0):
            for c in (0.0, 1.5, 3.0):
                rows.append(f"{a},0,{b},{c},0.1,0.2,0.3")
    grid.write_text("\n".join(rows) + "\n")
    brdf = patina.load_brdf(grid)
    assert brdf.info()["format"] == "csv" and [a["knots"] for a in brdf.info()["axes"]] == [3, 3, 3]
    scattered = tmp_path / "scattered.csv"
    ti, to, pd = rng.uniform(0, 1.2, 500), rng.uniform(0, 1.2, 500), rng.uniform(0, 3.1, 500)
    scattered.write_text(
        "theta_i,phi_i,theta_o,phi_o,R,G,B\n" + "".join(f"{a},0,{b},{c},0.1,0.2,0.3\n" for a, b, c in zip(ti, to, pd))
    )
    assert "resampled from 500" in patina.load_brdf(scattered).info()["provenance"]
    bad = tmp_path / "bad.csv"
    bad.write_text("0,0,0.1,0.2,1,2,3\n")
    with pytest.raises(patina.FormatError, match="header row"):
        patina.load_brdf(bad)
    bad.write_text("theta_i,phi_i,theta_o,phi_o,R,G,B\n0,0,0.1,0.2,1,2\n")
    with pytest.raises(patina.FormatError, match="line 2"):
        patina.load_brdf(bad)


# issue 10, defect 4 -------------------------------------------------------------------


def astm_rows(path, rows) -> None:
    lines = ["#ASTM E1392-96", "VARS theta_i phi_i theta_s phi_s R G B"]
    lines += [" ".join(f"{v:.7g}" for v in r) for r in rows]
    path.write_text("\n".join(lines) + "\n")


def degenerate_cases():
    line = [[0.0, 0.0, t, 2 * t, 0.1, 0.2, 0.3] for t in np.linspace(0.1, 1.2, 12)]  # theta_i = 0, phi = 2 theta_o
    twin = [[0.3, 0.0, 0.5, 1.0, 0.1, 0.2, 0.3], [0.5, 0.0, 0.3, 1.0, 0.1, 0.2, 0.3]]
    same_phi = [[a, 0.0, b, 0.7, 0.1, 0.2, 0.3] for a, b in np.random.default_rng(0).uniform(0, 1.4, (20, 2))]
    return {
        "one row": ([[0.1, 0.0, 0.5, 1.0, 0.1, 0.2, 0.3]], "distinct scattered point"),
        "collinear": (line, "lie on one plane"),  # with its reciprocal twins: a plane
        "two reciprocal rows": (twin, "distinct scattered points"),
        "one phi_d": (same_phi, "same phi_d"),
    }


@pytest.mark.parametrize("case", list(degenerate_cases()))
@pytest.mark.parametrize("command", ["info", "validate", "fit", "convert"])
def test_degenerate_scattered_data_is_a_format_error_in_every_command(tmp_path, capsys, case, command):
    from patina.cli import main

    rows, message = degenerate_cases()[case]
    path = tmp_path / "d.astm"
    astm_rows(path, rows)
    args = [command, str(path)] + ([str(tmp_path / "o.ptab")] if command == "convert" else [])
    assert main(args) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "(grid)" in err and message in err and "Qhull" not in err
    with pytest.raises(patina.FormatError, match=r"cannot be resampled|needs at least"):
        patina.load_brdf(path)


def test_isotropic_scattered_data_is_resampled_reciprocally(tmp_path):
    """A measurement's few incidence angles and many viewing angles: each sample stands for
    its swapped pair too, so the grid is reciprocal (without: 3 % at the 95th percentile here)."""
    from patina.table import validate

    rng = np.random.default_rng(0)
    n = 1439
    ti = np.radians(rng.choice([0, 15, 30, 45, 60, 75], n))
    to, pd = rng.uniform(0, np.radians(85), n), rng.uniform(0, np.pi, n)
    rgb = MODEL(angles_to_directions(ti, 0 * ti), angles_to_directions(to, pd))
    lines = ["#ASTM E1392-96", "VARS theta_i phi_i theta_s phi_s R G B"]
    lines += [f"{a:.7g} 0 {b:.7g} {c:.7g} {v[0]:.7g} {v[1]:.7g} {v[2]:.7g}" for a, b, c, v in zip(ti, to, pd, rgb)]
    path = tmp_path / "s.astm"
    path.write_text("\n".join(lines) + "\n")
    brdf = patina.load_brdf(path)
    assert brdf.axes[0].size == brdf.axes[1].size and np.array_equal(brdf.axes[0], brdf.axes[1])
    report = validate(brdf)
    assert report.checks["reciprocity"]["p95"] < 1e-3
    assert "resampled from 1439 scattered points" in brdf.info()["provenance"]  # info reports the error
