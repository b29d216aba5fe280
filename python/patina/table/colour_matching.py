"""The weights that take spectral samples to XYZ and linear sRGB, through colour-science:
the CIE 1931 2-degree observer under D65, on a table's own (possibly irregular)
wavelengths. Apart from spectral.py (which converts whole tables) so that a reader can
convert while reading without importing the table machinery (the RGL reader does).
"""

from __future__ import annotations

import warnings

import numpy as np


def colour_science():  # colour-science warns at import that SciPy is absent: nothing used here needs it
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        import colour
    return colour


def xyz_weights(wavelengths: np.ndarray) -> np.ndarray:
    """(3, C) weights taking C spectral samples at `wavelengths` (nm) to XYZ under D65."""
    colour = colour_science()
    lam = np.asarray(wavelengths, dtype=np.float64)
    if lam.ndim != 1 or lam.size < 2 or np.any(np.diff(lam) <= 0):
        raise ValueError("wavelengths must be at least two strictly increasing values (nm)")
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    d65 = colour.SDS_ILLUMINANTS["D65"]
    cmf = np.stack([np.interp(lam, cmfs.wavelengths, cmfs.values[:, i], left=0, right=0) for i in range(3)])
    illuminant = np.interp(lam, d65.wavelengths, d65.values, left=0, right=0)
    dl = np.empty_like(lam)  # trapezoid widths
    dl[1:-1] = (lam[2:] - lam[:-2]) / 2
    dl[0] = (lam[1] - lam[0]) / 2
    dl[-1] = (lam[-1] - lam[-2]) / 2
    weights = cmf * illuminant * dl
    sums = weights.sum(axis=1)
    if not np.all(sums > 0):
        raise ValueError("the wavelengths do not overlap the visible range of the CIE 1931 observer")
    # Each row scaled so that a flat spectrum lands exactly on D65's white point: with a
    # few, irregular wavelengths the plain quadrature would tint white (15% off in R at 7).
    white = np.asarray(colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"], dtype=np.float64)
    white_xyz = np.array([white[0] / white[1], 1.0, (1 - white[0] - white[1]) / white[1]])
    return weights * (white_xyz / sums)[:, None]


def xyz_to_linear_srgb() -> np.ndarray:
    return np.asarray(colour_science().RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB, dtype=np.float64)
