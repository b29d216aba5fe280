"""The analytic sphere (scene key `analytic` on a sphere shape, docs/scene.md): the white
furnace's exact answer, the same image bits at every SIMD width and thread count, the
tessellated sphere's tangent frame (an anisotropic conductor looks the same on both), and
`_core.Accel`'s sphere arguments."""

from __future__ import annotations

import os

import numpy as np
import pytest

from patina.native import _core
from patina.render.run import render
from patina.scene.reading import parse_scene
from repo_paths import ROOT

SIZE = (48, 36)


def sphere_scene(material: dict, analytic: bool, spp: int, environment: dict | None = None,
                 transform: dict | None = None) -> dict:  # fmt: skip
    shape = {"type": "sphere", "material": "m", "radius": 1, "analytic": analytic}
    if transform is not None:
        shape["transform"] = transform
    return {
        "version": 1,
        "camera": {"position": [0, 0.4, 4.5], "look_at": [0, 0, 0], "fov": 30, "width": SIZE[0], "height": SIZE[1]},
        "render": {"spp": spp, "integrator": "direct", "seed": 1},
        "materials": {"m": material},
        "shapes": [shape],
        "environment": environment or {"type": "constant", "radiance": 1.0},
    }


def rendered(obj: dict, **kwargs):
    return render(parse_scene(obj, os.path.join(ROOT, "materials", "scenes", "test.json")), **kwargs)


def test_white_furnace_gives_the_albedo_on_the_whole_sphere():
    """A Lambert sphere of albedo 0.5 under a uniform environment of 1 reflects exactly 0.5 (a
    convex surface sees only the environment); the background is 1."""
    result = rendered(sphere_scene({"type": "lambert", "albedo": 0.5}, True, 64), threads=2)
    hit = np.isfinite(result.depth)
    interior = hit.copy()  # pixels wholly on the sphere: their neighbours hit it too
    for axis in (0, 1):
        for step in (1, -1):
            interior &= np.roll(hit, step, axis=axis)
    assert interior.sum() > 300
    rgb = result.rgb.astype(np.float64)
    assert np.allclose(rgb[~hit], 1.0)
    on = rgb[interior]
    assert abs(on.mean() / 0.5 - 1) < 0.01, on.mean()
    assert np.abs(on / 0.5 - 1).max() < 0.25
    # the exact normal: unit, and at the centre pixel facing the camera
    n = result.normal[interior].astype(np.float64)
    assert np.allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)


def test_every_width_and_thread_count_gives_the_same_bits():
    """Widths 1, 8, 16 (those this CPU runs) and 1 or 2 threads: every AOV bit for bit, on an
    anisotropic gold sphere turned about two axes under the studio map."""
    obj = sphere_scene(
        {"type": "conductor", "metal": "Au", "roughness": [0.05, 0.3]},
        True,
        4,
        {"type": "map", "file": "../env/studio.exr"},
        {"rotate": [[[1, 0, 0], 30], [[0, 0, 1], 20]], "scale": 0.8, "translate": [0.1, 0, 0]},
    )
    widths = [w for w in (1, 8, 16) if _core.width_supported(w)]
    first = rendered(obj, threads=1, simd=widths[0])
    for w in widths:
        for threads in (1, 2):
            other = rendered(obj, threads=threads, simd=w)
            for aov in ("rgb", "albedo", "normal", "depth", "samples"):
                assert np.array_equal(getattr(first, aov), getattr(other, aov)), (aov, w, threads)


def _blocks(image: np.ndarray, block: int = 6) -> np.ndarray:
    h, w = image.shape[0] // block, image.shape[1] // block
    return image[: h * block, : w * block].reshape(h, block, w, block, -1).mean(axis=(1, 3))


def test_anisotropic_highlights_turn_as_on_the_tessellated_sphere():
    """The analytic sphere's tangents run along its parallels about its object y axis, as the
    triangle sphere's: an anisotropic conductor (turned sphere) gives the same image on both
    (the same seed: correlated samples, measured 0.0018 of the mean over 6 x 6 blocks), while
    swapping the roughness axes (what a frame turned by 90 degrees would do) differs by 0.80."""
    env = {"type": "map", "file": "../env/studio.exr"}
    turned = {"rotate": [[[1, 0, 0], 40], [[0, 1, 0], 25]]}
    aniso = {"type": "conductor", "metal": "Au", "roughness": [0.04, 0.35]}
    swapped = {**aniso, "roughness": [0.35, 0.04]}
    exact = rendered(sphere_scene(aniso, True, 256, env, turned), threads=2).rgb.astype(np.float64)
    facets = rendered(sphere_scene(aniso, False, 256, env, turned), threads=2).rgb.astype(np.float64)
    other = rendered(sphere_scene(swapped, True, 256, env, turned), threads=2).rgb.astype(np.float64)
    mean = exact.mean()

    def regional(a: np.ndarray, b: np.ndarray) -> float:
        return float(np.sqrt(((_blocks(a) - _blocks(b)) ** 2).mean()) / mean)

    same, turned_frame = regional(exact, facets), regional(exact, other)
    assert same < 0.02, same
    assert turned_frame > 0.3, (same, turned_frame)


def test_core_accel_traces_spheres_after_the_triangles():
    """Primitive ids: the triangles first, then the spheres; hit normals point outwards; the
    same hits through the BVH; bad spheres are refused naming the sphere."""
    v = np.array([[5, -1, -1], [5, 1, -1], [5, 0, 1]], np.float32)
    f = np.array([[0, 1, 2]], np.int32)
    accel = _core.Accel(v, f, spheres=np.array([[0, 0, 0, 1], [0, 3, 0, 0.5]], np.float32))
    assert accel.sphere_count == 2 and accel.triangle_count == 1
    o = np.array([[-5, 0, 0], [0, 3, -5], [10, 0, 0], [0, 10, 0]], np.float32)
    d = np.array([[1, 0, 0], [0, 0, 1], [-1, 0, 0], [0, 1, 0]], np.float32)
    for bvh in (False, True):
        t, prim, _, _, normal = accel.intersect(o, d, bvh=bvh)
        assert prim.tolist() == [1, 2, 0, -1]
        assert np.allclose(t[:3], [4, 4.5, 5])
        assert np.allclose(normal[:2], [[-1, 0, 0], [0, 0, -1]])
        assert accel.occluded(o, d, tmax=np.array([4.5, 4.4, 4.9, 9], np.float32), bvh=bvh).tolist() == [
            True, False, False, False]  # fmt: skip
    for bad in ([[0, 0, 0, 0]], [[np.nan, 0, 0, 1]]):
        with pytest.raises(ValueError, match="sphere 0"):
            _core.Accel(v, f, spheres=np.array(bad, np.float32))
