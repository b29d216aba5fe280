"""The exact irradiance a polygonal Lambertian emitter gives a point: the reference of the
renders under a quad light (tests/python/render/test_run.py, test_sampler.py)."""

from __future__ import annotations

import numpy as np


def rectangle_irradiance(p: np.ndarray, corners: np.ndarray) -> np.ndarray:
    """Irradiance on an upward-facing point from a unit-radiance polygon (Lambert's contour integral)."""
    e = np.zeros(p.shape[:-1])
    for a, b in zip(corners, np.roll(corners, -1, axis=0)):
        va, vb = a - p, b - p
        va /= np.linalg.norm(va, axis=-1, keepdims=True)
        vb /= np.linalg.norm(vb, axis=-1, keepdims=True)
        angle = np.arccos(np.clip((va * vb).sum(-1), -1, 1))
        cross = np.cross(va, vb)
        n = np.linalg.norm(cross, axis=-1)
        e += angle * cross[..., 1] / np.maximum(n, 1e-12)
    return np.abs(e) / 2
