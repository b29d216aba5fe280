"""Spectral tables to XYZ / linear sRGB (colour-science, CIE 1931 2 deg, D65)."""

from __future__ import annotations

import numpy as np
import pytest

import patina
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData
from patina.table.spectral import to_rgb, xyz_weights

AXES = [np.linspace(0, 1.5, 4), np.linspace(0, 1.5, 5), np.linspace(0, np.pi, 6)]


def spectral_table(values_per_wavelength: np.ndarray, wavelengths: np.ndarray) -> patina.Brdf:
    values = np.broadcast_to(values_per_wavelength, (4, 5, 6, wavelengths.size)).astype(np.float32)
    data = TableData("isotropic", AXES, values, "spectral", wavelengths=wavelengths, provenance="test")
    return patina.Brdf(table_from_data(data), "spectral-test", "test")


@pytest.mark.parametrize(
    "wavelengths", [np.arange(380.0, 781.0, 10.0), np.array([400.0, 430, 470, 520, 580, 650, 720])]
)
def test_a_flat_spectrum_becomes_grey(wavelengths):
    flat = spectral_table(np.full(wavelengths.size, 0.3), wavelengths)
    rgb = to_rgb(flat)
    assert rgb.channel_kind == "rgb" and rgb.channels == 3
    np.testing.assert_allclose(rgb.values, 0.3, rtol=0.01)  # D65 white is sRGB white
    xyz = to_rgb(flat, "xyz")
    np.testing.assert_allclose(xyz.values[..., 1], 0.3, rtol=1e-6)  # Y normalised to the flat spectrum


@pytest.mark.filterwarnings("ignore")  # colour-science notes how it aligns D65 to the observer
def test_weights_match_colour_science_integration():
    from patina.table.spectral import colour_science

    colour = colour_science()
    lam = np.arange(380.0, 781.0, 5.0)
    spectrum = np.exp(-0.5 * ((lam - 560) / 30) ** 2)
    ours = xyz_weights(lam) @ spectrum
    sd = colour.SpectralDistribution(dict(zip(lam, spectrum)))
    theirs = colour.sd_to_XYZ(sd, illuminant=colour.SDS_ILLUMINANTS["D65"]) / 100
    np.testing.assert_allclose(ours, theirs, rtol=0.02)


def test_spectral_tables_are_fitted_incolour_science():
    lam = np.arange(400.0, 701.0, 20.0)
    table = spectral_table(np.full(lam.size, 0.2), lam)
    from patina.fitting import table_samples

    measured = table_samples(table)[2]
    np.testing.assert_allclose(measured, 0.2, rtol=0.01)
    with pytest.raises(ValueError, match="not spectral"):
        to_rgb(to_rgb(table))
