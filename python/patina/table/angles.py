"""Angle conventions of the tables: polar/azimuth angles and Rusinkiewicz half/difference
angles to unit direction pairs in the local frame (z = the normal), in double precision."""

from __future__ import annotations

from typing import Any

import numpy as np


def angles_to_directions(theta: Any, phi: Any) -> np.ndarray:
    """Unit vectors (n, 3) in the local frame (z = normal) from polar/azimuth angles in radians."""
    t = np.asarray(theta, dtype=np.float64)
    p = np.asarray(phi, dtype=np.float64)
    s = np.sin(t)
    return np.stack([s * np.cos(p), s * np.sin(p), np.cos(t)], axis=-1)


def halfdiff_to_directions(
    theta_h: np.ndarray, theta_d: np.ndarray, phi_d: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Rusinkiewicz (theta_h, phi_h = 0, theta_d, phi_d) to (wi, wo)."""
    th, td, pd = (np.asarray(v, dtype=np.float64).ravel() for v in (theta_h, theta_d, phi_d))
    d = angles_to_directions(td, pd)
    # rotate the difference vector by theta_h about y (phi_h = 0)
    c, s = np.cos(th), np.sin(th)
    wi = np.stack([c * d[:, 0] + s * d[:, 2], d[:, 1], -s * d[:, 0] + c * d[:, 2]], axis=1)
    h = np.stack([s, np.zeros_like(s), c], axis=1)
    wo = 2.0 * np.sum(wi * h, axis=1, keepdims=True) * h - wi
    return wi, wo
