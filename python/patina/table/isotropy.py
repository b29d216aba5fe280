"""Whether a table's values depend on the azimuth of the plane of incidence: an anisotropic
grid (theta_i, phi_i, theta_o, phi_o) may hold an isotropic material -- UTIA files and WINDOW
Klems documents are four-dimensional whatever they measured -- and a fit's verdict should
judge the material, not its grid.

The measure: random pairs of directions within 60 deg of the normal, each pair turned about
the normal by a random angle; the cosine-weighted RMS of the change in the mean over
channels, relative to the cosine-weighted RMS of the values. Measured: an isotropic plastic
written as a UTIA file 0.002 (its 15 x 7.5 deg grid's interpolation), LBNL's anisotropic
Klems shade 0.10, the bundled brushed metal 0.59."""

from __future__ import annotations

import math

import numpy as np

from patina.table.angles import angles_to_directions
from patina.table.brdf import Brdf

ISOTROPIC_WITHIN = 0.05  # a table whose azimuth dependence is below this is taken as isotropic
PAIRS = 8192


def _turned(w: np.ndarray, angle: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * w[:, 0] - s * w[:, 1], s * w[:, 0] + c * w[:, 1], w[:, 2]], axis=1)


def azimuth_dependence(brdf: Brdf, pairs: int = PAIRS, seed: int = 3) -> float:
    """The relative change of the table's values when a pair of directions turns about the
    normal (0 for an isotropic parametrization, by construction)."""
    if brdf.parametrization != "anisotropic":
        return 0.0
    rng = np.random.default_rng(seed)
    wi, wo = (
        angles_to_directions(np.arccos(rng.uniform(0.5, 1.0, pairs)), rng.uniform(0, 2 * math.pi, pairs))
        for _ in range(2)
    )
    angle = rng.uniform(0, 2 * math.pi, pairs)
    f = brdf.eval(wi.astype(np.float32), wo.astype(np.float32)).astype(np.float64).mean(axis=1)
    turned = brdf.eval(_turned(wi, angle).astype(np.float32), _turned(wo, angle).astype(np.float32))
    g = turned.astype(np.float64).mean(axis=1)
    weight = wi[:, 2] * wo[:, 2]
    scale = np.sum(weight * (0.5 * (f + g)) ** 2)
    return float(np.sqrt(np.sum(weight * (f - g) ** 2) / scale)) if scale > 0 else 0.0


def is_anisotropic(brdf: Brdf) -> bool:
    """Whether the table's values depend on the azimuth beyond ISOTROPIC_WITHIN."""
    return azimuth_dependence(brdf) > ISOTROPIC_WITHIN
