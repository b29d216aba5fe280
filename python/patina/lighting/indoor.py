"""Indoor figures of EN 12464-1: the maintained illuminance Em and uniformity U0 over an area,
the maintenance factor, and the unified glare rating UGR of CIE 117:1995.

MF = LLMF x LSF x LMF x RSMF (CIE 97:2005): lamp lumen maintenance, lamp survival, luminaire
maintenance and room surface maintenance factors, each in (0, 1].

UGR = 8 log10(0.25 / L_b x sum L^2 omega / p^2) for an observer's eye looking horizontally:
L the luminance of a luminaire's luminous area towards the eye (I / A_p, cd/m^2), omega its
solid angle (A_p / r^2), A_p the luminous area projected towards the eye, p Guth's position
index (the approximation evalglare and CIE 117's users use:
ln p = (35.2 - 0.31889 tau - 1.22 exp(-2 tau / 9)) 1e-3 sigma + (21 + 0.26667 tau -
0.002963 tau^2) 1e-5 sigma^2, with sigma the angle between the line of sight and the
luminaire and tau the angle from the vertical of the plane through both, in degrees), L_b the
background luminance E_ind / pi from the indirect illuminance at the eye. Only luminaires
above the line of sight and ahead of the eye count (the position index is for those).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError
from patina.lighting.direct import PlacedSource, arrivals

MF_PARTS = ("LLMF", "LSF", "LMF", "RSMF")


def maintenance_factor(parts: dict[str, float], where: str) -> float:
    """The product of the parts given (missing ones are 1); each must lie in (0, 1]."""
    mf = 1.0
    for key, value in parts.items():
        if key not in MF_PARTS:
            raise FormatError(
                where, f"maintenance.{key}", f"not a maintenance factor part (one of {', '.join(MF_PARTS)})"
            )
        if isinstance(value, bool) or not isinstance(value, int | float) or not 0 < value <= 1:
            raise FormatError(where, f"maintenance.{key}", f"expected a number in (0, 1], got {value!r}")
        mf *= float(value)
    return mf


@dataclass(frozen=True)
class AreaFigures:
    em: float
    e_min: float
    e_max: float

    @property
    def u0(self) -> float:
        return self.e_min / self.em if self.em > 0 else 0.0


def area_figures(lux: np.ndarray) -> AreaFigures:
    e = np.asarray(lux, np.float64)
    return AreaFigures(float(e.mean()), float(e.min()), float(e.max()))


def position_index(sigma_deg: np.ndarray, tau_deg: np.ndarray) -> np.ndarray:
    s, t = np.asarray(sigma_deg, np.float64), np.asarray(tau_deg, np.float64)
    return np.exp(
        (35.2 - 0.31889 * t - 1.22 * np.exp(-2 * t / 9)) * 1e-3 * s + (21 + 0.26667 * t - 0.002963 * t**2) * 1e-5 * s**2
    )


def ugr(
    sources: list[PlacedSource],
    areas: list[float],
    eye: np.ndarray,
    sight_azimuth_deg: float,
    background: float,
    occluder=None,
    offset: float = 1e-4,
) -> float:
    """CIE 117 UGR at `eye` looking horizontally towards azimuth (degrees from +x towards +z);
    `areas`: each luminaire's flat horizontal luminous area (m^2, from its photometric file's
    opening); `background`: L_b in cd/m^2. Below 10 no glare is worth a figure: returned as is."""
    if background <= 0:
        raise FormatError("command line", "background luminance", f"must be positive, got {background:g}")
    a = math.radians(sight_azimuth_deg)
    sight = np.array([math.cos(a), 0.0, math.sin(a)])
    arr = arrivals(sources, np.asarray(eye, np.float64)[None, :], occluder, offset)
    total = 0.0
    for i, area in enumerate(areas):
        r = arr.towards[i, 0]
        cos_sigma = float(r @ sight)
        if arr.candela[i, 0] <= 0 or cos_sigma <= 0 or r[1] <= 0 or area <= 0:
            continue
        sigma = math.degrees(math.acos(min(cos_sigma, 1.0)))
        across = r - cos_sigma * sight  # r in the plane normal to the line of sight
        tau = math.degrees(math.atan2(abs(across @ np.cross(sight, [0.0, 1.0, 0.0])), across[1]))
        projected = area * r[1]  # a horizontal luminous area seen from below at elevation asin(r_y)
        luminance = arr.candela[i, 0] / projected
        omega = projected / arr.d2[i, 0]
        total += luminance**2 * omega / float(position_index(sigma, tau)) ** 2
    if total <= 0:
        return -math.inf
    return 8 * math.log10(0.25 / background * total)
