"""A Lambert plane under a quad light and its exact answer (Lambert's polygon form factor,
box-filtered over each pixel): the reference of tests/python/render/test_run.py's and
test_sampler.py's renders under a quad light."""

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


CORNERS = np.array([[-0.5, 1, 0.3], [0.5, 1, 0.3], [0.5, 1, -0.3], [-0.5, 1, -0.3]])  # the light, 1 m up
RADIANCE = 2.0


def quad_light_scene(size: int, spp: int) -> dict:
    """The scene file: a white Lambert floor seen from 5 m above, direct light, seed 1."""
    return {
        "version": 1,
        "camera": {"position": [0, 5, 0.01], "look_at": [0, 0, 0], "fov": 50, "width": size, "height": size},
        "render": {"spp": spp, "integrator": "direct", "seed": 1},
        "materials": {"white": {"type": "lambert", "albedo": 1.0}},
        "shapes": [{"type": "plane", "material": "white", "size": [8, 8]}],
        "lights": [{"type": "quad", "center": [0, 1, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.3], "radiance": RADIANCE}],
    }


def quad_light_floor(camera, sub: int) -> tuple[np.ndarray, np.ndarray]:
    """The floor's exact radiance per pixel (the field box-filtered over sub x sub points, as
    the renderer's pixels are; albedo 1: radiance E / pi), and where the pixels see the floor
    under the light's outline (its dark back hides it there)."""
    ys, xs = np.mgrid[0 : camera.height * sub, 0 : camera.width * sub] + 0.5
    d = camera.ray_direction(xs / sub, ys / sub)
    p = np.asarray(camera.position) + (-camera.position[1] / d[..., 1])[..., None] * d

    def box(a: np.ndarray) -> np.ndarray:
        return a.reshape(camera.height, sub, camera.width, sub).mean(axis=(1, 3))

    expected = box(RADIANCE * rectangle_irradiance(p, CORNERS) / np.pi)
    under = box(((np.abs(p[..., 0]) < 0.6) & (np.abs(p[..., 2]) < 0.4)).astype(float)) > 0
    return expected, under
