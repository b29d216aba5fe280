"""Spectral tables to XYZ and linear sRGB, through colour-science.

A spectral BRDF value per wavelength is treated like a spectral reflectance factor:
XYZ_c = W_c sum_k cmf_c(l_k) D65(l_k) f(l_k) dl_k / sum_k cmf_c(l_k) D65(l_k) dl_k, with
the CIE 1931 2-degree observer, trapezoid weights on the table's own (possibly
irregular) wavelengths, zero outside the observer's range, and W the D65 white point
(Y = 1). So a spectrally flat table becomes the same value in Y and, through the sRGB
matrix, in R, G and B, however coarse its wavelengths. The spectral table
itself stays available; conversion makes a new one.
"""

from __future__ import annotations

import warnings

import numpy as np

from patina.table.brdf import Brdf
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData


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


def to_rgb(brdf: Brdf, space: str = "srgb") -> Brdf:
    """A spectral table as an XYZ or linear-sRGB one (same grid, mask and symmetries)."""
    if space not in ("srgb", "xyz"):
        raise ValueError(f"space '{space}': expected srgb or xyz")
    if brdf.channel_kind != "spectral":
        raise ValueError(f"the table is {brdf.channel_kind}, not spectral")
    m = xyz_weights(brdf.wavelengths)
    if space == "srgb":
        m = xyz_to_linear_srgb() @ m
    note = (
        f"converted from {brdf.channels} wavelengths to "
        f"{'linear sRGB' if space == 'srgb' else 'XYZ'} (CIE 1931 2 deg, D65)"
    )
    return _with_values(brdf, brdf.values.astype(np.float64) @ m.T, "rgb" if space == "srgb" else "xyz", note)


def as_linear_srgb(brdf: Brdf) -> Brdf:
    """The table with linear-sRGB channels: RGB as it is, spectral and XYZ converted (CIE
    1931 2 deg, D65), a single channel repeated."""
    kind = brdf.channel_kind
    if kind == "rgb":
        return brdf
    if kind == "spectral":
        return to_rgb(brdf)
    values = brdf.values.astype(np.float64)
    if kind == "xyz":
        values = values @ xyz_to_linear_srgb().T
    else:
        values = np.repeat(values.reshape(-1, 1), 3, axis=1)
    return _with_values(brdf, values, "rgb", f"{kind} shown as linear sRGB")


def _with_values(brdf: Brdf, values: np.ndarray, channel_kind: str, note: str) -> Brdf:
    """The same grid, mask and symmetries with other channel values; `note` joins the provenance."""
    info = brdf.info()
    data = TableData(
        parametrization=brdf.parametrization,
        axes=[a.astype(np.float64) for a in brdf.axes],
        values=values.astype(np.float32),
        channel_kind=channel_kind,
        units=info["units"],
        provenance=f"{info['provenance']}; {note}",
        mask=brdf.valid,
        symmetry=set(info["symmetry"]),
    )
    return Brdf(table_from_data(data), brdf.source, brdf.source_format)
