"""Spectra from linear-sRGB values by the method Mitsuba 3 uses for RGB upsampling (Jakob &
Hanika 2019, "A Low-Dimensional Function Space for Efficient Spectral Upsampling"): each
colour has three coefficients c, fetched from Mitsuba's own precomputed sRGB table
(`srgb_model_fetch` of the installed `mitsuba` package), and the spectrum is the sigmoid of
a quadratic in the wavelength (nm), s(l) = 1/2 + x / (2 sqrt(1 + x^2)), x = c0 l^2 + c1 l + c2.

The model holds reflectances within [0, 1]; a BRDF value is unbounded, so each colour is
first divided by twice its largest component and the spectrum multiplied back, as Mitsuba
upsamples an unbounded emitter colour (its `d65` spectrum given a `color`: the same spectrum
times D65). Mitsuba's `srgb` reflectance texture would look the colour up as it is, which
loses the scale of values above 1. Upsampling is then linear in a colour's scale (k rgb
becomes k s), so values that are the same colour times different factors (an RGL file's
stored values) upsample consistently.
"""

from __future__ import annotations

import importlib.util

import numpy as np

WAVELENGTHS = np.arange(360.0, 831.0, 10.0)  # nm: Mitsuba's CIE range (MI_CIE_MIN .. MI_CIE_MAX)


class UpsamplingUnavailable(ValueError):
    """The `mitsuba` package (whose coefficient table is used) is not installed."""


def _fetch():
    if importlib.util.find_spec("mitsuba") is None:
        raise UpsamplingUnavailable(
            "spectra from RGB need the mitsuba package (its Jakob-Hanika sRGB table): "
            "pip install mitsuba==3.9.1, or write RGB only"
        )
    from mitsuba import scalar_spectral  # the variant's module: no global mi.set_variant

    return scalar_spectral.srgb_model_fetch, scalar_spectral.Color3f


def sigmoid_spectrum(coefficients: np.ndarray, wavelengths: np.ndarray) -> np.ndarray:
    """(n, 3) coefficients -> (n, len(wavelengths)) values of the sigmoid-quadratic spectra."""
    c = np.asarray(coefficients, dtype=np.float64)
    lam = np.asarray(wavelengths, dtype=np.float64)[None, :]
    x = c[:, 0:1] * lam * lam + c[:, 1:2] * lam + c[:, 2:3]
    return 0.5 + x / (2.0 * np.sqrt(1.0 + x * x))


def upsample(rgb: np.ndarray, wavelengths: np.ndarray = WAVELENGTHS) -> np.ndarray:
    """(n, 3) linear-sRGB values (any scale, negatives clamped to 0) -> (n, len(wavelengths))."""
    fetch, color = _fetch()
    rgb = np.maximum(np.asarray(rgb, dtype=np.float64).reshape(-1, 3), 0.0)
    scale = 2.0 * rgb.max(axis=1)
    lit = scale > 0
    unit = np.zeros_like(rgb)
    unit[lit] = rgb[lit] / scale[lit, None]
    # the table is a lookup of float32 colours: fetch each distinct one once
    keys, inverse = np.unique(unit.astype(np.float32), axis=0, return_inverse=True)
    coefficients = np.array([list(fetch(color(*(float(v) for v in k)))) for k in keys], dtype=np.float64)
    out = sigmoid_spectrum(coefficients, wavelengths)[inverse.ravel()] * scale[:, None]
    out[~lit] = 0.0
    return out
