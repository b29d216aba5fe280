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

import numpy as np

from patina.table.brdf import Brdf
from patina.table.colour_matching import colour_science, xyz_to_linear_srgb, xyz_weights
from patina.table.formats import table_from_data
from patina.table.formats.tabledata import TableData

__all__ = ["as_linear_srgb", "colour_science", "to_rgb", "xyz_to_linear_srgb", "xyz_weights"]


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
