"""The bundled car-paint base table (materials/carpaint-base.ptab) and the model it samples."""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import patina
from patina.synthetic.carpaint import PAINTS, base_brdf, coated_base, coated_paint, dielectric_fresnel, refract_in
from patina.synthetic.carpaint_table import BUNDLED_PAINT, base_table, interpolation_errors, peak_pairs, random_pairs
from patina.table.brdf import angles_to_directions
from repo_paths import ROOT

BUNDLED = os.path.join(ROOT, "materials", "carpaint-base.ptab")
PAINT = PAINTS[BUNDLED_PAINT]


@pytest.fixture(scope="module")
def bundled() -> patina.Brdf:
    return patina.load_brdf(BUNDLED)


def test_regenerating_gives_the_bundled_values(bundled: patina.Brdf) -> None:
    data = base_table(PAINT)
    assert bundled.parametrization == "halfdiff"
    for axis, knots in zip(bundled.axes, data.axes):
        np.testing.assert_allclose(axis, knots, rtol=0, atol=1e-6)
    np.testing.assert_allclose(bundled.values, data.values, rtol=1e-6, atol=0)
    assert set(bundled.info()["symmetry"]) == {"reciprocity", "phi_mirror"}
    assert os.path.getsize(BUNDLED) < 1_000_000


def test_bundled_table_validates_clean(bundled: patina.Brdf) -> None:
    report = patina.validate(bundled)
    assert report.ok, report.problems
    assert report.checks["albedo"]["max"] <= 1.0
    assert report.checks["reciprocity"]["max"] < 1e-4


def test_table_matches_the_model_within_the_stated_error(bundled: patina.Brdf) -> None:
    # the figures in materials/carpaint-base.md, with a margin for the smaller sample
    rng = np.random.default_rng(11)
    model = coated_base(PAINT)
    anywhere = interpolation_errors(bundled, model, *random_pairs(30_000, rng))
    assert anywhere.median < 0.001
    assert anywhere.p99 < 0.04
    near_peak = interpolation_errors(bundled, model, *peak_pairs(20_000, rng, 3.0))
    assert near_peak.p99 < 0.015
    at_peak = interpolation_errors(bundled, model, *peak_pairs(20_000, rng, 1.0))
    assert at_peak.max < 0.005


def test_base_at_normal_incidence_is_the_closed_form() -> None:
    # wi = wo = n: D = 1 / m^2, G = 1, Schlick F = F0, so f = kd / pi + sum ks F0 / (pi m^2)
    n = np.array([[0.0, 0.0, 1.0]])
    expected = np.array(PAINT.kd) / math.pi
    for ks, r, m in zip(PAINT.ks, PAINT.r, PAINT.m):
        expected = expected + np.array(ks) * r / (math.pi * m * m)
    np.testing.assert_allclose(base_brdf(PAINT)(n, n)[0], expected, rtol=1e-12)


@pytest.mark.parametrize("name", sorted(PAINTS))
def test_every_paint_is_reciprocal(name: str) -> None:
    rng = np.random.default_rng(3)
    wi, wo = random_pairs(2000, rng, 89.0)
    f = coated_paint(PAINTS[name])
    np.testing.assert_allclose(f(wi, wo), f(wo, wi), rtol=1e-10)


def test_refraction_follows_snell() -> None:
    theta = np.radians(np.linspace(0.0, 89.9, 50))
    w = angles_to_directions(theta, np.full_like(theta, 0.7))
    t = refract_in(w, 1.5)
    np.testing.assert_allclose(np.linalg.norm(t, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(np.hypot(t[:, 0], t[:, 1]), np.sin(theta) / 1.5, atol=1e-12)
    np.testing.assert_allclose(np.arctan2(t[1:, 1], t[1:, 0]), 0.7, atol=1e-9)


def test_fresnel_at_normal_and_grazing() -> None:
    np.testing.assert_allclose(dielectric_fresnel(np.array([1.0, 0.0])), [0.04, 1.0], atol=1e-12)


def test_coat_plus_table_is_the_published_model(bundled: patina.Brdf) -> None:
    """What the renderer does, (1 - F_i)(1 - F_o) table, against the model's glossy part from outside."""
    rng = np.random.default_rng(5)
    wi, wo = random_pairs(20_000, rng)
    wi32, wo32 = wi.astype(np.float32), wo.astype(np.float32)
    attenuation = (1 - dielectric_fresnel(wi32[:, 2])) * (1 - dielectric_fresnel(wo32[:, 2]))
    rendered = bundled.eval(wi32, wo32) * attenuation[:, None]
    exact = coated_paint(PAINT)(wi32.astype(np.float64), wo32.astype(np.float64))
    rel = np.abs(rendered - exact) / exact
    assert np.median(rel) < 0.001
    assert np.percentile(rel, 99) < 0.04


def test_outside_albedo_stays_below_one() -> None:
    """Coat reflectance plus the attenuated base, integrated over the outside hemisphere, at a few incidences."""
    f = coated_paint(PAINT)
    # cos-weighted quadrature over the outside hemisphere, dense enough for the 2-deg lobe: half-vector grid
    for theta_i in np.radians([0.0, 40.0, 75.0]):
        wi = angles_to_directions(theta_i, 0.0)
        u = (np.arange(1500) + 0.5) / 1500
        th = (math.pi / 2) * u**3
        dth = (math.pi / 2) * 3 * u**2 / 1500
        ph = (np.arange(360) + 0.5) * (2 * math.pi / 360)
        t, p = np.meshgrid(th, ph, indexing="ij")
        h = angles_to_directions(t.ravel(), p.ravel())
        dh = (np.sin(t) * dth[:, None] * (2 * math.pi / 360)).ravel()
        ih = h @ wi
        wo = 2 * ih[:, None] * h - wi
        ok = (ih > 0) & (wo[:, 2] > 0)
        weight = 4 * ih[ok] * dh[ok] * wo[ok, 2]  # d omega_o = 4 (wi . h) d omega_h
        glossy = weight @ f(np.broadcast_to(wi, wo.shape)[ok], wo[ok])
        total = glossy + dielectric_fresnel(np.array([math.cos(theta_i)]))[0]
        assert np.all(total <= 1.0), (math.degrees(theta_i), total)
        assert np.all(glossy > 0.05)
