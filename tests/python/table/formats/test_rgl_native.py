"""The native RGL evaluator, pdf and sampler (_core.RglBsdf, brdf/rgl/) against the
double-precision reference (rgl_brdf.RglBrdf, rgl_warp.Interpolant2D) on files written by
rgl_writer: isotropic and anisotropic (full and reduced azimuthal range), RGB and spectral,
within float precision; the sampler's directions distributed as its pdf (chi-square), and
that pdf following the luminance of f cos(theta_o) it is built from."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2

from patina.synthetic.analytic import plastic
from patina.table.angles import angles_to_directions
from patina.table.formats.rgl_brdf import RglBrdf, elevation, phi_to_u, theta_to_u
from patina.table.formats.rgl_native import native_rgl
from patina.table.formats.rgl_writer import RglLayout, rgl_arrays
from patina.table.formats.tensor_file import parse_tensor_file, tensor_file_bytes

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)
SMALL = RglLayout(theta_i=6, ndf=(8, 16), sigma=(8, 16), vndf=(12, 16), values=(12, 12))
ANISOTROPIC = RglLayout(theta_i=5, phi_i=7, ndf=(8, 16), sigma=(8, 16), vndf=(12, 16), values=(12, 12))
WAVELENGTHS = np.linspace(400, 700, 7)


def _brdf(arrays: dict[str, np.ndarray], name: str) -> RglBrdf:
    return RglBrdf(parse_tensor_file(name, tensor_file_bytes(arrays)))


def _reduced(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The same grids declared over phi_i in [0, pi]: a file of half the azimuthal range."""
    arrays = dict(arrays)
    arrays["phi_i"] = np.linspace(0, math.pi, arrays["phi_i"].size).astype(np.float32)
    return arrays


@pytest.fixture(scope="module")
def materials() -> dict[str, RglBrdf]:
    anisotropic = rgl_arrays(MODEL, layout=ANISOTROPIC)
    grey = lambda wi, wo: MODEL(wi, wo)[:, 1:2] * np.linspace(0.4, 1.0, WAVELENGTHS.size)  # noqa: E731
    return {
        "isotropic rgb": _brdf(rgl_arrays(MODEL, layout=SMALL), "iso.bsdf"),
        "isotropic spectral": _brdf(rgl_arrays(grey, WAVELENGTHS, layout=SMALL), "spectral.bsdf"),
        "anisotropic rgb": _brdf(anisotropic, "aniso.bsdf"),
        "anisotropic half range": _brdf(_reduced(anisotropic), "half.bsdf"),
    }


def _pairs(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Uniform over the hemisphere, a quarter of them near the mirror direction, a few grazing."""
    rng = np.random.default_rng(seed)
    wi = angles_to_directions(np.arccos(rng.uniform(0.02, 1, n)), rng.uniform(0, 2 * math.pi, n))
    wo = angles_to_directions(np.arccos(rng.uniform(0.02, 1, n)), rng.uniform(0, 2 * math.pi, n))
    mirror = wi[: n // 4] * np.array([-1.0, -1.0, 1.0]) + rng.normal(scale=0.1, size=(n // 4, 3))
    mirror[:, 2] = np.abs(mirror[:, 2]) + 0.02
    wo[: n // 4] = mirror / np.linalg.norm(mirror, axis=1, keepdims=True)
    return wi.astype(np.float32), wo.astype(np.float32)


def _relative(native: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Relative error, with a floor of 1e-3 of the largest value (f spans four decades).
    Measured (20000 pairs): median 2e-7, 99.9% 1e-5 (3e-5 on the half-range file), max 3e-4."""
    floor = 1e-3 * np.abs(reference).max()
    return np.abs(native - reference) / np.maximum(np.abs(reference), floor)


@pytest.mark.parametrize("name", ["isotropic rgb", "isotropic spectral", "anisotropic rgb", "anisotropic half range"])
def test_evaluation_matches_the_double_precision_reference(materials, name):
    brdf = materials[name]
    native = native_rgl(brdf)
    wi, wo = _pairs(6000, seed=1)
    reference = brdf.eval(wi.astype(np.float64), wo.astype(np.float64))
    for width in (1, 0):
        rel = _relative(native.eval(wi, wo, width=width), reference)
        assert np.median(rel) < 2e-6 and np.percentile(rel, 99.9) < 1e-4 and rel.max() < 2e-3, (width, rel.max())


def test_below_the_horizon_is_zero(materials):
    native = native_rgl(materials["isotropic rgb"])
    wi = np.array([[0.3, 0.0, 0.954], [0.3, 0.0, -0.954], [0.0, 0.6, 0.8]], np.float32)
    wo = np.array([[-0.2, 0.1, -0.97], [0.0, 0.0, 1.0], [0.0, -0.6, 0.0]], np.float32)
    assert np.all(native.eval(wi, wo) == 0) and np.all(native.pdf(wi, wo) == 0)
    # non-finite directions read no memory outside the grids (every index is clamped)
    bad = np.array([[np.nan, 0.0, 0.8], [np.inf, 0.1, 0.9], [0.1, -np.inf, np.inf]], np.float32)
    for width in (1, 0):
        assert native.eval(bad, wi[[2, 2, 2]], width=width).shape == (3, 3)
        assert native.pdf(wi[[2, 2, 2]], bad, width=width).shape == (3,)


def _reference_pdf(brdf: RglBrdf, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """The density of wo under sampling by the luminance then the VNDF warp, in double."""
    a, b = brdf._fold(wi, wo)
    m = a + b
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    theta_i, phi_i = elevation(a), np.arctan2(a[:, 1], a[:, 0])
    phi_m = np.arctan2(m[:, 1], m[:, 0])
    u_m = np.stack([theta_to_u(elevation(m)), phi_to_u(phi_m - phi_i if brdf.isotropic else phi_m)], axis=1)
    u_m[:, 1] -= np.floor(u_m[:, 1])
    s, vndf_pdf = brdf.vndf.invert(u_m, [phi_i, theta_i])
    luminance_pdf = brdf.luminance.eval(s, [phi_i, theta_i])
    sin_m = np.hypot(m[:, 0], m[:, 1])
    jacobian = np.maximum(2 * math.pi**2 * u_m[:, 0] * sin_m, 1e-6) * 4 * np.sum(a * m, axis=1)
    return vndf_pdf * luminance_pdf / jacobian


@pytest.mark.parametrize("name", ["isotropic rgb", "anisotropic half range"])
def test_pdf_matches_the_reference(materials, name):
    brdf = materials[name]
    wi, wo = _pairs(4000, seed=2)
    rel = _relative(native_rgl(brdf).pdf(wi, wo), _reference_pdf(brdf, wi.astype(np.float64), wo.astype(np.float64)))
    assert np.median(rel) < 2e-6 and np.percentile(rel, 99.9) < 1e-4 and rel.max() < 1e-3


def _bin_edges() -> tuple[np.ndarray, np.ndarray]:
    return np.linspace(0, 1, 17), np.linspace(-math.pi, math.pi, 33)  # cos(theta_o), phi_o


def _expected_counts(native, wi: np.ndarray, samples: int) -> np.ndarray:
    """The pdf integrated over each (cos theta, phi) bin by the midpoint rule, 12 x 12 per bin."""
    cos_edges, phi_edges = _bin_edges()
    fine = 12
    cos_mid = np.linspace(0, 1, (cos_edges.size - 1) * fine + 1)
    cos_mid = 0.5 * (cos_mid[1:] + cos_mid[:-1])
    phi_mid = np.linspace(-math.pi, math.pi, (phi_edges.size - 1) * fine + 1)
    phi_mid = 0.5 * (phi_mid[1:] + phi_mid[:-1])
    c, p = np.meshgrid(cos_mid, phi_mid, indexing="ij")
    wo = angles_to_directions(np.arccos(c.ravel()), p.ravel()).astype(np.float32)
    pdf = native.pdf(np.repeat(wi[None, :], len(wo), axis=0), wo).astype(np.float64)
    cell = (1.0 / cos_mid.size) * (2 * math.pi / phi_mid.size)
    per_bin = pdf.reshape(cos_edges.size - 1, fine, phi_edges.size - 1, fine).sum(axis=(1, 3)) * cell
    return per_bin * samples


@pytest.mark.parametrize("name", ["isotropic rgb", "anisotropic rgb"])
@pytest.mark.parametrize("theta_deg", [20.0, 60.0])
def test_samples_are_distributed_as_the_pdf(materials, name, theta_deg):
    native = native_rgl(materials[name])
    wi = angles_to_directions(np.radians(theta_deg), 0.7).astype(np.float32)
    samples = 200_000
    rng = np.random.default_rng(int(theta_deg))
    wo, pdf = native.sample(np.repeat(wi[None, :], samples, axis=0), rng.random((samples, 2), dtype=np.float32))
    kept = pdf > 0
    expected = _expected_counts(native, wi, samples)
    # the pdf's mass over the hemisphere is the share of samples that stay above it
    assert abs(expected.sum() / samples - kept.mean()) < 0.01
    cos_edges, phi_edges = _bin_edges()
    observed, _, _ = np.histogram2d(wo[kept, 2], np.arctan2(wo[kept, 1], wo[kept, 0]), bins=[cos_edges, phi_edges])
    enough = expected > 20  # bins with fewer expected samples are pooled into one
    statistic = np.sum((observed[enough] - expected[enough]) ** 2 / expected[enough])
    rest_observed, rest_expected = observed[~enough].sum(), expected[~enough].sum()
    if rest_expected > 20:
        statistic += (rest_observed - rest_expected) ** 2 / rest_expected
    dof = int(enough.sum())
    assert chi2.sf(statistic, dof) > 1e-3, (statistic, dof)


def test_pdf_follows_the_luminance_of_the_reflected_energy(materials):
    """The luminance warp is Y(f cos theta_o) at the sample points: the pdf is that shape
    normalised, up to the warps' bilinear interpolation."""
    brdf = materials["isotropic rgb"]
    native = native_rgl(brdf)
    wi = angles_to_directions(np.radians(35.0), 0.3).astype(np.float32)
    rng = np.random.default_rng(9)
    wo = angles_to_directions(np.arccos(rng.uniform(0.05, 1, 20000)), rng.uniform(0, 2 * math.pi, 20000))
    wo = wo.astype(np.float32)
    wis = np.repeat(wi[None, :], len(wo), axis=0)
    energy = native.eval(wis, wo) @ np.array([0.2126, 0.7152, 0.0722]) * wo[:, 2]
    pdf = native.pdf(wis, wo)
    # both normalised over the hemisphere by the same uniform sample (area 2 pi)
    shape = energy / (energy.mean() * 2 * math.pi)
    density = pdf / (pdf.mean() * 2 * math.pi)
    significant = shape > 0.2 * shape.max()
    assert np.median(np.abs(density[significant] / shape[significant] - 1)) < 0.1


@pytest.mark.parametrize("name", ["isotropic rgb", "anisotropic half range"])
def test_sampling_estimator_mean_is_the_albedo(materials, name):
    """White furnace: the mean of f cos(theta_o) / pdf over the sampler's directions is the
    directional albedo, integral of f cos(theta_o) over the hemisphere (here by a 256 x 512
    midpoint rule in (cos theta_o, phi_o))."""
    native = native_rgl(materials[name])
    wi = angles_to_directions(np.radians(40.0), 2.0).astype(np.float32)
    cos_o = (np.arange(256) + 0.5) / 256
    phi_o = (np.arange(512) + 0.5) / 512 * 2 * math.pi - math.pi
    c, p = np.meshgrid(cos_o, phi_o, indexing="ij")
    grid = angles_to_directions(np.arccos(c.ravel()), p.ravel()).astype(np.float32)
    f = native.eval(np.repeat(wi[None, :], len(grid), axis=0), grid).astype(np.float64)
    albedo = (f * grid[:, 2:3]).sum(axis=0) * (2 * math.pi / len(grid))
    samples = 200_000
    rng = np.random.default_rng(12)
    wis = np.repeat(wi[None, :], samples, axis=0)
    wo, pdf = native.sample(wis, rng.random((samples, 2), dtype=np.float32))
    kept = pdf > 0
    weight = np.zeros((samples, 3))
    weight[kept] = native.eval(wis[kept], wo[kept]) * wo[kept, 2:3] / pdf[kept, None]
    mean, error = weight.mean(axis=0), weight.std(axis=0) / math.sqrt(samples)
    assert np.all(np.abs(mean - albedo) < 4 * error + 2e-3 * albedo), (mean, albedo, error)
