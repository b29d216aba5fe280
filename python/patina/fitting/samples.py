"""The table's grid points as the samples a fit runs on: direction pairs, measured RGB and
cosine weights, the solid-angle measure each grid point stands for, and random subsets
drawn in proportion to that measure for the search's stages.

Why the measure: measured grids are irregular on purpose (knots dense near the specular
peak), so a loss summed over grid points weighs the peak by its knot density, not by the
directions it covers. On the bundled car paint (theta_h's median knot 5 deg from the
peak) such a loss barely sees the diffuse term and a Ward fit ended with its diffuse
albedo at the bound (1, 1, 1): a blue paint fitted white. Drawing the samples in
proportion to the measure makes the loss an integral over pairs of directions.
"""

from __future__ import annotations

import math

import numpy as np

from patina.kernel_arrays import as_float32
from patina.table.angles import angles_to_directions, halfdiff_to_directions
from patina.table.brdf import Brdf
from patina.table.spectral import as_linear_srgb


def _axis_measure(name: str, knots: np.ndarray) -> np.ndarray:
    """Each knot's share of its axis: the integral of the axis's Jacobian factor over the
    knot's cell (from the midpoint to each neighbour, clipped at the axis ends), so a knot
    at theta = 0 keeps the small cap around it."""
    k = knots.astype(np.float64)
    edges = np.concatenate([[k[0]], 0.5 * (k[1:] + k[:-1]), [k[-1]]])
    a, b = edges[:-1], edges[1:]
    if name == "theta_d":  # dw_i dw_o = 4 cos(theta_d) dw_h dw_d
        return 0.5 * (np.sin(b) ** 2 - np.sin(a) ** 2)
    if name.startswith("theta"):  # solid angle: sin(theta) dtheta dphi
        return np.cos(a) - np.cos(b)
    return b - a


def _grid(brdf: Brdf, max_theta_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[np.ndarray]]:
    """(wi, wo, keep mask, per-axis angle grids) of every grid point, in C order."""
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
    limit = math.cos(math.radians(max_theta_deg))
    keep = (wi[:, 2] > limit) & (wo[:, 2] > limit)
    if brdf.valid is not None:
        keep &= brdf.valid.ravel().astype(bool)
    return wi, wo, keep, flat


def table_samples(brdf: Brdf, max_theta_deg: float = 80.0) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The table's grid points as direction pairs: (wi, wo, measured linear sRGB, cos_i cos_o weights).

    Measured values are the table's own (no interpolation); missing points and pairs
    beyond max_theta_deg from the normal are left out.
    """
    # fits are of reflected colour in linear sRGB: spectral and XYZ converted (D65), and a
    # monochrome measurement (a Zemax or goniophotometer file often is one) fitted as grey
    brdf = as_linear_srgb(brdf)
    wi, wo, keep, _ = _grid(brdf, max_theta_deg)
    values = brdf.values.reshape(-1, 3).astype(np.float64)
    keep &= np.isfinite(values).all(axis=1)
    weight = wi[keep, 2] * wo[keep, 2]
    return as_float32(wi[keep]), as_float32(wo[keep]), as_float32(values[keep]), as_float32(weight)


def sample_measure(brdf: Brdf, max_theta_deg: float = 80.0) -> np.ndarray:
    """The measure of direction pairs each sample of table_samples stands for (same order).

    The product of the axes' cell measures (_axis_measure): sin(theta) for each polar
    angle, and for half/difference angles sin(theta_h) sin(theta_d) cos(theta_d), since
    dw_i dw_o = 4 cos(theta_d) dw_h dw_d. Only ratios matter (samples are drawn in proportion)."""
    _, _, keep, _ = _grid(brdf, max_theta_deg)
    parts = np.meshgrid(*[_axis_measure(n, a) for n, a in zip(brdf.axis_names, brdf.axes)], indexing="ij")
    cell = np.prod([p.ravel() for p in parts], axis=0)
    values = brdf.values.reshape(-1, brdf.channels)
    keep &= np.isfinite(values).all(axis=1)
    measure = cell[keep]
    # a grid whose every kept knot has zero measure (theta = 0 only) falls back to uniform
    return measure if measure.sum() > 0 else np.ones_like(measure)


def subset(
    arrays: tuple[np.ndarray, ...], n: int, rng: np.random.Generator, measure: np.ndarray | None = None
) -> tuple[np.ndarray, ...]:
    """n samples: without a measure a plain random subset (all when there are at most n);
    with one, min(n, count) draws with replacement in proportion to it."""
    count = len(arrays[0])
    if measure is None:
        if count <= n:
            return arrays
        pick = np.sort(rng.choice(count, n, replace=False))
    else:
        pick = np.sort(rng.choice(count, min(n, count), replace=True, p=measure / measure.sum()))
    return tuple(np.ascontiguousarray(a[pick]) for a in arrays)
