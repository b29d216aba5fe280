#!/usr/bin/env python3
"""Renders the built-in shapes (patina.geometry.shapes) to a PNG for a look: primary rays through
patina.Accel, n.l shading.

    PYTHONPATH=python .venv/bin/python tools/view_shapes.py [OUT.png] [--size 320]

Top row: the preview ball from the front-above and from the side, the car panel at a
grazing angle (its feature line shows as a step in shading). Bottom row: the same with
the interpolated tangent field as colour, to check it is smooth. A quick check of the
geometry and shading frames, not a renderer.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from patina import Accel
from patina.geometry.shapes import ShapeMesh, car_panel, plane, preview_ball


def _camera(eye: np.ndarray, target: np.ndarray, size: int, fov_deg: float) -> tuple[np.ndarray, np.ndarray]:
    forward = (target - eye) / np.linalg.norm(target - eye)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    s = math.tan(math.radians(fov_deg) / 2)
    y, x = np.mgrid[0:size, 0:size]
    u = ((x + 0.5) / size * 2 - 1) * s
    v = (1 - (y + 0.5) / size * 2) * s
    d = forward + u[..., None] * right + v[..., None] * up
    d = (d / np.linalg.norm(d, axis=-1, keepdims=True)).reshape(-1, 3)
    return np.broadcast_to(eye, d.shape).astype(np.float32), d.astype(np.float32)


def _shade(shapes: list[ShapeMesh], eye: list[float], target: list[float], size: int, fov: float) -> list[np.ndarray]:
    accel = Accel([s.mesh(f"s{i}") for i, s in enumerate(shapes)])
    o, d = _camera(np.asarray(eye, float), np.asarray(target, float), size, fov)
    hits = accel.intersect(o, d)
    shade = np.full((len(d), 3), 0.15)
    tangent = np.full((len(d), 3), 0.15)
    light = np.array([0.5, 0.8, 0.6]) / np.linalg.norm([0.5, 0.8, 0.6])
    for k, s in enumerate(shapes):
        sel = hits.mesh == k
        tri = s.indices[hits.local_prim[sel]]
        w = np.stack([1 - hits.u[sel] - hits.v[sel], hits.u[sel], hits.v[sel]], axis=1)[..., None]
        n = np.sum(s.normals[tri] * w, axis=1)
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        t = np.sum(s.tangents[tri] * w, axis=1)
        t /= np.linalg.norm(t, axis=1, keepdims=True)
        lit = 0.1 + 0.85 * np.clip(n @ light, 0, 1) + 0.25 * np.clip(n @ -light, 0, 1) * 0.3
        shade[sel] = lit[:, None] * [0.9, 0.85, 0.8]
        tangent[sel] = 0.5 + 0.5 * t
    return [shade.reshape(size, size, 3), tangent.reshape(size, size, 3)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default="/tmp/patina-shapes.png")
    parser.add_argument("--size", type=int, default=320)
    args = parser.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ball, floor = preview_ball(), plane((8.0, 8.0))
    views = [
        _shade([ball, floor], [0.0, 2.6, 4.2], [0.0, 1.0, 0.0], args.size, 40),
        _shade([ball, floor], [4.4, 1.5, 0.8], [0.0, 1.0, 0.0], args.size, 40),
        _shade([car_panel()], [1.2, 0.9, 2.2], [0.0, 0.0, 0.0], args.size, 50),
    ]
    fig, axes = plt.subplots(2, 3, figsize=(12, 8))
    for col, (shade, tangent) in enumerate(views):
        axes[0, col].imshow(np.clip(shade, 0, 1))
        axes[1, col].imshow(np.clip(tangent, 0, 1))
    for ax in axes.ravel():
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(args.out, dpi=80)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
