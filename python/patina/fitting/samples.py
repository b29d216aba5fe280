"""The table's grid points as the samples a fit runs on: direction pairs, measured RGB and
cosine weights, and random subsets of them for the search's stages."""

from __future__ import annotations

import math

import numpy as np

from patina.table.angles import angles_to_directions, halfdiff_to_directions
from patina.table.brdf import Brdf
from patina.table.spectral import to_rgb


def table_samples(brdf: Brdf, max_theta_deg: float = 80.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The table's grid points as direction pairs: (wi, wo, measured RGB, cos_i cos_o weights).

    Measured values are the table's own (no interpolation); missing points and pairs
    beyond max_theta_deg from the normal are left out.
    """
    if brdf.channel_kind == "spectral":
        brdf = to_rgb(brdf)  # fits are of reflected colour: linear sRGB under D65
    if brdf.channels != 3:
        raise ValueError(f"fitting needs an RGB, XYZ or spectral table; this one has {brdf.channels} channel(s)")
    grids = np.meshgrid(*[a.astype(np.float64) for a in brdf.axes], indexing="ij")
    flat = [g.ravel() for g in grids]
    if brdf.parametrization == "isotropic":
        wi = angles_to_directions(flat[0], np.zeros_like(flat[0]))
        wo = angles_to_directions(flat[1], flat[2])
    elif brdf.parametrization == "anisotropic":
        wi = angles_to_directions(flat[0], flat[1])
        wo = angles_to_directions(flat[2], flat[3])
    else:
        wi, wo = halfdiff_to_directions(*flat)
    values = brdf.values.reshape(-1, 3).astype(np.float64)
    keep = (wi[:, 2] > math.cos(math.radians(max_theta_deg))) & (wo[:, 2] > math.cos(math.radians(max_theta_deg)))
    if brdf.valid is not None:
        keep &= brdf.valid.ravel().astype(bool)
    keep &= np.isfinite(values).all(axis=1)
    weight = wi[keep, 2] * wo[keep, 2]
    as32 = lambda a: np.ascontiguousarray(a, dtype=np.float32)  # noqa: E731
    return as32(wi[keep]), as32(wo[keep]), as32(values[keep]), as32(weight)


def subset(arrays: tuple[np.ndarray, ...], n: int, rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    count = len(arrays[0])
    if count <= n:
        return arrays
    pick = np.sort(rng.choice(count, n, replace=False))
    return tuple(np.ascontiguousarray(a[pick]) for a in arrays)
