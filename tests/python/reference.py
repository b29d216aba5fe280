"""A plain double-precision reference for table evaluation: numpy, no SIMD, no fast math.

The same definitions as brdf/eval.h (angles, folding, clamping, multilinear
interpolation, renormalisation over measured corners), written independently.
"""

from __future__ import annotations

import numpy as np

RECIPROCITY, PHI_MIRROR = 1, 2


def coords(parametrization: str, symmetry: int, wi: np.ndarray, wo: np.ndarray) -> list[np.ndarray]:
    wi = np.asarray(wi, np.float64)
    wo = np.asarray(wo, np.float64)
    if parametrization == "halfdiff":
        h = wi + wo
        h /= np.linalg.norm(h, axis=1, keepdims=True)
        th = np.arccos(np.clip(h[:, 2], -1, 1))
        ph = np.arctan2(h[:, 1], h[:, 0])
        c, s = np.cos(-ph), np.sin(-ph)
        t0, t1, t2 = c * wi[:, 0] - s * wi[:, 1], s * wi[:, 0] + c * wi[:, 1], wi[:, 2]
        c, s = np.cos(-th), np.sin(-th)
        d0, d1, d2 = c * t0 + s * t2, t1, -s * t0 + c * t2
        pd = np.arctan2(d1, d0)
        if symmetry & RECIPROCITY:
            pd = np.where(pd < 0, pd + np.pi, pd)
        if symmetry & PHI_MIRROR:
            pd = np.abs(pd)
            pd = np.where(pd > np.pi / 2, np.pi - pd, pd)
        return [th, np.arccos(np.clip(d2, -1, 1)), pd]
    ti = np.arccos(np.clip(wi[:, 2], -1, 1))
    to = np.arccos(np.clip(wo[:, 2], -1, 1))
    if parametrization == "isotropic":
        cross = wi[:, 0] * wo[:, 1] - wi[:, 1] * wo[:, 0]
        dot = wi[:, 0] * wo[:, 0] + wi[:, 1] * wo[:, 1]
        if symmetry & RECIPROCITY:
            ti, to = np.minimum(ti, to), np.maximum(ti, to)
        return [ti, to, np.arctan2(np.abs(cross), dot)]
    pi = np.mod(np.arctan2(wi[:, 1], wi[:, 0]), 2 * np.pi)
    po = np.mod(np.arctan2(wo[:, 1], wo[:, 0]), 2 * np.pi)
    if symmetry & RECIPROCITY:
        swap = ti > to
        ti, to = np.where(swap, to, ti), np.where(swap, ti, to)
        pi, po = np.where(swap, po, pi), np.where(swap, pi, po)
    return [ti, pi, to, po]


def evaluate(table, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """Reference values (n, channels) for a patina._core.Table or patina.Brdf."""
    t = getattr(table, "table", table)
    axes = [a.astype(np.float64) for a in t.axes]
    values = t.values.astype(np.float64).reshape(-1, t.channels)
    valid = None if t.valid is None else t.valid.reshape(-1).astype(np.float64)
    c = coords(t.parametrization, t.symmetry, wi, wo)
    dims = len(axes)
    strides = np.cumprod([1] + [len(a) for a in axes[::-1]])[:-1][::-1]
    cells, fracs = [], []
    for a, x in zip(axes, c):
        i = np.clip(np.searchsorted(a, x, side="right") - 1, 0, len(a) - 2)
        cells.append(i)
        fracs.append(np.clip((x - a[i]) / (a[i + 1] - a[i]), 0.0, 1.0))
    out = np.zeros((len(c[0]), t.channels))
    covered = np.zeros(len(c[0]))
    for k in range(1 << dims):
        w = np.ones(len(c[0]))
        point = np.zeros(len(c[0]), dtype=np.int64)
        for a in range(dims):
            upper = (k >> (dims - 1 - a)) & 1
            w = w * (fracs[a] if upper else 1 - fracs[a])
            point += (cells[a] + upper) * strides[a]
        if valid is not None:
            w = w * valid[point]
        covered += w
        out += w[:, None] * values[point]
    if valid is not None:
        out = np.where(covered[:, None] > 0, out / np.where(covered > 0, covered, 1)[:, None], 0.0)
    below = (np.asarray(wi)[:, 2] <= 0) | (np.asarray(wo)[:, 2] <= 0)
    out[below] = 0.0
    return out


def hemisphere(n: int, seed: int, below: float = 0.0) -> np.ndarray:
    """n unit vectors, uniform over the upper hemisphere (a fraction `below` mirrored under it)."""
    rng = np.random.default_rng(seed)
    z = rng.uniform(0, 1, n)
    z[rng.uniform(0, 1, n) < below] *= -1
    phi = rng.uniform(0, 2 * np.pi, n)
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1).astype(np.float32)
