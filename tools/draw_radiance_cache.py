"""Draws the radiance cache's pictures (docs/radiance-cache.md) from the renderer's own code
(patina.native._core.cache_probe: a cache point built, reprojected and its holes traced
by render/cache/), on the bundled Cornell box (materials/scenes/area-box.json).

    .venv/bin/python tools/draw_radiance_cache.py [--out docs/images]

Writes radiance-cache-point.png (a cache point's incident-radiance texture, hit distance,
depth layers and merged surfels), radiance-cache-reprojection.png (a nearby point's fill,
unknown and to-trace masks, the reprojected texture, after tracing the holes, and its own
hemisphere traced in full) and radiance-cache-leak.png (the same reprojection without the
unknown masks, against with them, where the wall shows through the sphere's unseen side).
Each panel is a hemisphere in the equal-area square parametrization (u right, v up).
"""

from __future__ import annotations

import argparse
import os

import numpy as np

from patina.atomic import atomic_output
from patina.render.prepare import PreparedScene
from patina.scene.reading import load_scene

ROOT = os.path.join(os.path.dirname(__file__), "..")
SCENE = os.path.join(ROOT, "materials", "scenes", "area-box.json")
DPI = 90
RESOLUTION = 64
# on the floor beside the large sphere (centre (-0.4, 0.4, -0.3), radius 0.4), B a step away
A, B, UP = (0.15, 0.0, -0.1), (0.3, 0.0, 0.05), (0.0, 1.0, 0.0)


def _save(fig, path: str) -> None:
    atomic_output(path, lambda tmp: fig.savefig(tmp, dpi=DPI, format="png", bbox_inches="tight"))
    print(f"wrote {path} ({os.path.getsize(path) // 1024} KB)")


def _tonemap(rgb: np.ndarray, scale: float) -> np.ndarray:
    x = np.clip(rgb, 0, None) * scale
    return np.clip(x / (1 + x), 0, 1) ** (1 / 2.2)


def _panel(ax, image: np.ndarray, title: str, **kw) -> None:
    ax.imshow(image, origin="lower", interpolation="nearest", **kw)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize=9)


def _holes(rgb: np.ndarray, scale: float) -> np.ndarray:
    """Tone-mapped radiance with the texels left to trace (marked -1) in magenta."""
    img = _tonemap(rgb, scale)
    img[rgb[..., 0] < 0] = (0.9, 0.1, 0.8)
    return img


def draw(out: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap

    from patina.native import _core

    prep = PreparedScene(load_scene(SCENE))
    probe = {
        masks: _core.cache_probe(
            prep.core, A, UP, B, UP, resolution=RESOLUTION, max_depth=4, seed=1, unknown_masks=masks
        )
        for masks in (True, False)
    }
    p = probe[True]
    scale = 1.0 / max(float(np.percentile(p.a_radiance, 99)), 1e-6)
    rng = np.random.default_rng(3)

    fig, axes = plt.subplots(1, 4, figsize=(12, 3.4))
    _panel(axes[0], _tonemap(p.a_radiance, scale), "A: incident indirect radiance")
    dist = np.where(np.isfinite(p.a_dist), p.a_dist, np.nan)
    _panel(axes[1], np.log(dist), "A: hit distance (log)", cmap="viridis")
    layers = np.where(p.a_layer >= 0, p.a_layer, np.nan)
    _panel(axes[2], layers, "A: depth layers", cmap="tab20", vmin=0, vmax=19)
    colours = ListedColormap(rng.uniform(0.2, 1.0, (max(int(p.surfels), 1), 3)))
    surfels = np.where(p.a_surfel >= 0, p.a_surfel, np.nan)
    _panel(axes[3], surfels, f"A: {p.surfels} surfels (merged blocks)", cmap=colours, vmin=0, vmax=p.surfels)
    fig.suptitle(f"a cache point on the floor of the Cornell box, {RESOLUTION} x {RESOLUTION} texels", fontsize=10)
    _save(fig, os.path.join(out, "radiance-cache-point.png"))
    plt.close(fig)

    fig, axes = plt.subplots(2, 3, figsize=(9.5, 6.6))
    grey = {"cmap": "gray", "vmin": 0, "vmax": 1}
    _panel(axes[0, 0], p.filled, "B: fill mask", **grey)
    _panel(axes[0, 1], p.unknown, "B: unknown (shadow) mask", **grey)
    _panel(axes[0, 2], p.to_trace, f"B: to trace ({100 * p.to_trace.mean():.1f} %)", **grey)
    _panel(axes[1, 0], _holes(p.b_reprojected, scale), "B: reprojected from A (holes magenta)")
    _panel(axes[1, 1], _tonemap(p.b_radiance, scale), "B: holes traced")
    _panel(axes[1, 2], _tonemap(p.b_reference, scale), "B: its own hemisphere traced")
    fig.suptitle(f"A reprojected into B, {np.linalg.norm(np.subtract(B, A)):.2f} m away", fontsize=10)
    _save(fig, os.path.join(out, "radiance-cache-reprojection.png"))
    plt.close(fig)

    fig, axes = plt.subplots(1, 3, figsize=(9.5, 3.4))
    q = probe[False]
    _panel(axes[0], _holes(q.b_reprojected, scale), "without unknown masks")
    _panel(axes[1], _holes(p.b_reprojected, scale), "with them")
    leak = (q.to_trace == 0) & (p.to_trace == 1)
    _panel(axes[2], leak, f"texels the masks stop ({int(leak.sum())})", **grey)
    fig.suptitle("B's reprojection: the wall A saw beside the sphere, seen through its side", fontsize=10)
    _save(fig, os.path.join(out, "radiance-cache-leak.png"))
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "images"))
    draw(os.path.normpath(ap.parse_args().out))


if __name__ == "__main__":
    main()
