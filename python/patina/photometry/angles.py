"""The mapping between a unit direction in the luminaire's own frame and the two angles of
its candela table, in radians (docs/luminaires.md; the renderer ports the same formulas).

Type C (h = C, v = gamma): luminaire -Z is nadir (gamma 0), +Z zenith (gamma pi); the C0
half-plane contains +X, C90 contains +Y (counter-clockwise seen from above):
    d = (sin v cos h, sin v sin h, -cos v);   v = acos(-dz), h = atan2(dy, dx) mod 2 pi.
Type B (h = H, v = V): the photometric axis (H = V = 0) is +Z, +Y is up and the planes of
constant V share the horizontal axis X; V turns the plane up about X, H is the angle within
the plane, positive towards -X (clockwise seen from above, as LM-63 counts type B):
    d = (-sin h, cos h sin v, cos h cos v);   h = asin(-dx), v = atan2(dy, dz).
"""

from __future__ import annotations

import numpy as np


def direction_of(h: np.ndarray, v: np.ndarray, kind: str = "C") -> np.ndarray:
    """Unit directions (..., 3) for table angles h, v (radians)."""
    h = np.asarray(h, np.float64)
    v = np.asarray(v, np.float64)
    if kind == "C":
        return np.stack(np.broadcast_arrays(np.sin(v) * np.cos(h), np.sin(v) * np.sin(h), -np.cos(v)), axis=-1)
    if kind == "B":
        return np.stack(np.broadcast_arrays(-np.sin(h), np.cos(h) * np.sin(v), np.cos(h) * np.cos(v)), axis=-1)
    raise ValueError(f"photometric type {kind!r}: 'C' or 'B'")


def angles_of(direction: np.ndarray, kind: str = "C") -> tuple[np.ndarray, np.ndarray]:
    """Table angles (h, v) in radians of directions (..., 3); they need not be normalised.

    Type C: h in [0, 2 pi), v in [0, pi]. Type B: h in [-pi/2, pi/2], v in (-pi, pi]."""
    d = np.asarray(direction, np.float64)
    norm = np.linalg.norm(d, axis=-1)
    norm = np.where(norm > 0, norm, 1.0)
    x, y, z = d[..., 0] / norm, d[..., 1] / norm, d[..., 2] / norm
    if kind == "C":
        return np.mod(np.arctan2(y, x), 2 * np.pi), np.arccos(np.clip(-z, -1.0, 1.0))
    if kind == "B":
        return np.arcsin(np.clip(-x, -1.0, 1.0)), np.arctan2(y, z)
    raise ValueError(f"photometric type {kind!r}: 'C' or 'B'")
