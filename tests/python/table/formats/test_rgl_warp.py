"""The RGL interpolants and warps (python/patina/table/formats/rgl_warp.py): sampling
inverts, the sampled points follow the density (chi-square), parameters interpolate."""

from __future__ import annotations

import numpy as np
from scipy import stats

from patina.table.formats.rgl_warp import Interpolant2D


def _density() -> np.ndarray:
    y, x = np.meshgrid(np.linspace(0, 1, 9), np.linspace(0, 1, 13), indexing="ij")
    first = 0.1 + np.exp(-((x - 0.3) ** 2 + (y - 0.6) ** 2) / 0.02)
    second = 0.2 + x * y
    return np.stack([first, second])  # one parameter with 2 values


def test_sample_then_invert_gives_the_uniform_point_back():
    warp = Interpolant2D(_density(), [np.array([0.0, 1.0])], warp=True)
    rng = np.random.default_rng(3)
    u = rng.uniform(0.001, 0.999, (2000, 2))
    p = rng.uniform(0, 1, 2000)
    pos, pdf = warp.sample(u, [p])
    back, pdf_back = warp.invert(pos, [p])
    assert np.allclose(back, u, atol=1e-5)  # the near-constant case is solved to first order, as the format does
    assert np.allclose(pdf, pdf_back, rtol=1e-9)
    assert np.allclose(warp.eval(pos, [p]), pdf, rtol=1e-9)


def test_samples_follow_the_density_chi_square():
    warp = Interpolant2D(_density(), [np.array([0.0, 1.0])], warp=True)
    n = 40000
    rng = np.random.default_rng(5)
    p = np.full(n, 0.25)
    pos, _ = warp.sample(rng.uniform(size=(n, 2)), [p])
    bins = 12
    counts, _, _ = np.histogram2d(pos[:, 0], pos[:, 1], bins=bins, range=[[0, 1], [0, 1]])
    # expected counts: the density integrated over each bin (fine midpoint rule)
    fine = (np.arange(bins * 8) + 0.5) / (bins * 8)
    gx, gy = np.meshgrid(fine, fine, indexing="ij")
    d = warp.eval(np.stack([gx.ravel(), gy.ravel()], 1), [np.full(gx.size, 0.25)]).reshape(gx.shape)
    expected = d.reshape(bins, 8, bins, 8).sum(axis=(1, 3))
    expected *= n / expected.sum()
    assert abs(d.mean() - 1.0) < 1e-3  # a density over the unit square
    chi2 = float(((counts - expected) ** 2 / expected).sum())
    assert stats.chi2.sf(chi2, bins * bins - 1) > 1e-3


def test_parameters_interpolate_linearly_and_clamp():
    values = np.stack([np.full((2, 2), 1.0), np.full((2, 2), 3.0)])
    table = Interpolant2D(values, [np.array([0.0, 2.0])])
    pos = np.full((4, 2), 0.5)
    assert np.allclose(table.eval(pos, [np.array([-1.0, 0.5, 1.0, 9.0])]), [1.0, 1.5, 2.0, 3.0])
