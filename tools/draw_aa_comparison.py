"""Draws the adaptive antialiasing beside what it replaces (docs/antialiasing.md, "Before and
after"): for each bundled AA scene at a preview's size (512 x 384), a magnified crop of one
ray a pixel (no antialiasing), 25 random rays a pixel, the adaptive sampler and the bench's
1024-ray reference, each titled with its rays a pixel and its RMSE against the reference over
the whole image (the time ratios are the bench's: `patina bench --only aa`).

    .venv/bin/python tools/draw_aa_comparison.py [--out docs/images/aa-before-after.png]

The reference is the bench's (patina.bench.aa.reference: kept on disk, made in 2-5 minutes a
scene when absent)."""

from __future__ import annotations

import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from patina.atomic import atomic_output
from patina.bench.aa import reference
from patina.bundled import materials_path
from patina.render.images import tonemap
from patina.render.outputs import auto_exposure
from patina.render.prepare import PreparedScene
from patina.render.run import render
from patina.scene.reading import load_scene, with_overrides

WIDTH, HEIGHT = 512, 384
# the crop of each scene (x, y, width, height in pixels of the 512 x 384 image): where its edges are hardest
CROPS = {
    "checkerboard": (208, 176, 96, 72),
    "converging-lines": (208, 176, 96, 72),
    "preview-ball": (170, 170, 96, 72),
    "wires": (220, 120, 96, 72),
}


def _renders(name: str):
    """(label, rgb, rays a pixel) of the three samplers, and the reference."""
    scene = load_scene(materials_path("scenes", f"aa-{name}.json"))
    scene = with_overrides(scene, spp=1, width=WIDTH, height=HEIGHT)
    prepared = PreparedScene(scene)
    samplers = [
        ("1 ray a pixel", scene, {"aa": "uniform"}),
        ("25 random rays", with_overrides(scene, spp=25), {"aa": "uniform", "sampler": "independent"}),
        ("adaptive", scene, {"aa": "adaptive"}),
    ]
    shown = []
    for label, job, options in samplers:
        result = render(job, prepared=prepared, **options)
        shown.append((label, result.rgb, result.camera_rays / (WIDTH * HEIGHT)))
    return shown, reference(scene)


def _crop(ax, rgb: np.ndarray, stops: float, title: str) -> None:
    ax.imshow(tonemap(rgb, stops, "filmic"), interpolation="nearest")
    ax.set_title(title, fontsize=9)
    ax.set_xticks([])
    ax.set_yticks([])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join("docs", "images", "aa-before-after.png"), help="the figure (PNG)")
    args = ap.parse_args()
    fig, axes = plt.subplots(len(CROPS), 4, figsize=(13.2, 2.75 * len(CROPS)), layout="constrained")
    for row, (name, (x, y, w, h)) in enumerate(CROPS.items()):
        shown, ref = _renders(name)
        stops = auto_exposure(ref)
        window = (slice(y, y + h), slice(x, x + w))
        for ax, (label, rgb, rays) in zip(axes[row], shown):
            rmse = float(np.sqrt(np.mean((rgb.astype(np.float64) - ref) ** 2)))
            _crop(ax, rgb[window], stops, f"{label}: {rays:.2f} rays/px\nRMSE {rmse:.4f}")
        _crop(axes[row, 3], ref[window], stops, "reference: 1024 stratified rays/px\n(8 x 8 strata of 16)")
        axes[row, 0].set_ylabel(name, fontsize=11)
    fig.suptitle(f"Adaptive antialiasing at {WIDTH} x {HEIGHT}: crops of {w} x {h} pixels, magnified", fontsize=12)
    atomic_output(args.out, lambda tmp: fig.savefig(tmp, dpi=80, format="png"))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
