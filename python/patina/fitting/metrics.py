"""How close a fit is: relative errors, and colour differences (CIEDE2000) between measured and
fitted reflected colours."""

from __future__ import annotations

import math

import numpy as np

from patina.table.spectral import colour_science


def colour_differences(measured: np.ndarray, fitted: np.ndarray, cos_i: np.ndarray) -> np.ndarray:
    """CIEDE2000 between measured and fitted reflected colours under D65.

    Each sample's linear-sRGB BRDF value times pi cos(theta_i) is the colour it reflects
    relative to a white Lambertian surface facing the light (1 = that white), taken to
    XYZ and CIELAB with the D65 white point."""
    colour = colour_science()
    to_xyz = np.linalg.inv(np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB, dtype=np.float64))
    white = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]["D65"]
    scale = (math.pi * np.asarray(cos_i, dtype=np.float64))[:, None]
    lab = [
        colour.XYZ_to_Lab(np.maximum(np.asarray(rgb, dtype=np.float64) * scale, 0.0) @ to_xyz.T, white)
        for rgb in (measured, fitted)
    ]
    return np.asarray(colour.delta_E(lab[0], lab[1], method="CIE 2000"))


def relative_errors(reference: np.ndarray, other: np.ndarray) -> np.ndarray:
    """|other - reference| / |reference|, elementwise, with |reference| floored at a thousandth of
    its median: where a measurement is near zero (grazing angles, far from a lobe) a tiny
    absolute miss would otherwise read as a huge relative one."""
    floor = 1e-3 * float(np.median(np.abs(reference))) + 1e-12
    return np.abs(other - reference) / np.maximum(np.abs(reference), floor)
