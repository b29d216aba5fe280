"""Colour and photometric constants shared by every part: Rec.709 luminance and 683 lm/W.

Patina's RGB is linear Rec.709 (sRGB primaries, D65 white) of the tristimulus values with
the CIE 1931 functions unnormalised, so 683 lm/W x Y is a photometric quantity (lumens,
candela, lux, cd/m^2) of the radiometric one (docs/render.md, docs/scene.md).
"""

from __future__ import annotations

import numpy as np

# lm/W: the maximum luminous efficacy, the factor from tristimulus Y (W) to lumens
LUMINOUS_EFFICACY = 683.0
# Rec.709 / sRGB luminance weights (Y row of the RGB to XYZ matrix)
LUMINANCE_WEIGHTS = np.array([0.2126, 0.7152, 0.0722])


def luminance(rgb: np.ndarray) -> np.ndarray:
    """Tristimulus Y (same unit as rgb) of linear Rec.709 values (..., 3)."""
    return np.asarray(rgb, dtype=np.float64) @ LUMINANCE_WEIGHTS


def photometric_to_rgb(value: float, color: tuple[float, float, float]) -> tuple[float, float, float]:
    """Patina's radiometric RGB for a photometric value (candela, cd/m^2, lux) of a colour:
    value / 683 lm/W x color / Y(color). The colour must have a positive luminance."""
    y = float(luminance(np.asarray(color)))
    if not y > 0:
        raise ValueError("the colour must have a positive luminance")
    r, g, b = (value / LUMINOUS_EFFICACY * c / y for c in color)
    return (r, g, b)
