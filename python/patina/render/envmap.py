"""Latitude-longitude environment map convention: pixels to directions and solid angles.

One convention for the whole project (the renderer, the bundled maps and the Mitsuba 3
cross-check): Mitsuba 3's `envmap`, y up. The point (u, v) of the map, u in [0, 1) from
left to right and v in [0, 1] from top to bottom, is the direction

    phi = 2 pi u,  theta = pi v,
    d = (sin(phi) sin(theta), cos(theta), -cos(phi) sin(theta)),

so the top row looks up (+y), the middle row is the horizon, u = 0 looks along -z and
u = 0.25 along +x. Pixel (row i, column j) of an H x W map covers u in [j, j + 1) / W and
v in [i, i + 1) / H; its centre is ((j + 0.5) / W, (i + 0.5) / H).

The maps store radiance in W/(m^2 sr) as linear Rec.709 (sRGB primaries, D65 white)
tristimulus values of the spectral radiance, with the CIE 1931 functions unnormalised, so
683 lm/W x (0.2126 R + 0.7152 G + 0.0722 B) is the luminance in cd/m^2 (and the same
factor turns an irradiance into illuminance in lux).
"""

from __future__ import annotations

import numpy as np


def lat_long_direction(u: np.ndarray | float, v: np.ndarray | float) -> np.ndarray:
    """Unit directions (..., 3) for map coordinates u (left to right) and v (top to bottom)."""
    phi = 2.0 * np.pi * np.asarray(u, dtype=np.float64)
    theta = np.pi * np.asarray(v, dtype=np.float64)
    sin_theta = np.sin(theta)
    return np.stack(np.broadcast_arrays(np.sin(phi) * sin_theta, np.cos(theta), -np.cos(phi) * sin_theta), axis=-1)


def direction_to_lat_long(d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Map coordinates (u in [0, 1), v in [0, 1]) of directions (..., 3); need not be unit length."""
    d = np.asarray(d, dtype=np.float64)
    norm = np.linalg.norm(d, axis=-1)
    y = np.clip(d[..., 1] / np.where(norm > 0.0, norm, 1.0), -1.0, 1.0)
    u = np.arctan2(d[..., 0], -d[..., 2]) / (2.0 * np.pi)
    u = np.where(u < 0.0, u + 1.0, u)
    # -0.0 / tiny negatives wrap to exactly 1.0 after the shift; 1.0 is the same column as 0
    u = np.where(u >= 1.0, 0.0, u)
    return u, np.arccos(y) / np.pi


def pixel_directions(height: int, width: int) -> np.ndarray:
    """Directions (height, width, 3) through the pixel centres of a height x width map."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    return lat_long_direction(u[None, :], v[:, None])


def solid_angles(height: int, width: int) -> np.ndarray:
    """Exact solid angle (sr) of each pixel, (height, width); the whole map sums to 4 pi."""
    if height <= 0 or width <= 0:
        raise ValueError(f"map size must be positive, got {height} x {width}")
    cos_edges = np.cos(np.pi * np.arange(height + 1) / height)
    # band between two rows: 2 pi (cos theta0 - cos theta1), split evenly among the columns
    rows = (2.0 * np.pi / width) * (cos_edges[:-1] - cos_edges[1:])
    return np.repeat(rows[:, None], width, axis=1)


def irradiance(rgb: np.ndarray, normal: tuple[float, float, float] = (0.0, 1.0, 0.0)) -> np.ndarray:
    """Irradiance (3,) on a plane facing `normal` (default up) from a radiance map (H, W, 3).

    The sum over pixels of radiance x cos(angle at the pixel centre) x pixel solid angle.
    """
    height, width = rgb.shape[:2]
    cosine = np.clip(pixel_directions(height, width) @ np.asarray(normal, dtype=np.float64), 0.0, None)
    weights = cosine * solid_angles(height, width)
    return np.einsum("hw,hwc->c", weights, np.asarray(rgb, dtype=np.float64))
