"""Draws the radiance cache's mosaic before and after a change (docs/radiance-cache.md, "The
mosaic"): renders side by side, tone-mapped, and under each its luminance error against a
converged reference with the 32-pixel region grid drawn, with each image's block-step
measure (patina.bench.block_steps) in its title.

    .venv/bin/python tools/draw_cache_mosaic.py --reference REF.exr --out FIG.png \\
        "before=BEFORE.exr" "after=AFTER.exr"

The renders are `patina render SCENE --integrator cache --spp 16 --out X.exr` by the builds
compared (an older build from a git worktree of its revision); the reference is `patina
render SCENE --integrator path --spp 4096 --seed 7 --out REF.exr`."""

from __future__ import annotations

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from patina.atomic import atomic_output
from patina.bench.block_steps import block_step_ratios, luminance
from patina.render.images import read_image, tonemap

REGION_PIXELS = 32


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reference", required=True, help="the converged reference render (EXR)")
    ap.add_argument("--out", required=True, help="the figure (PNG)")
    ap.add_argument("images", nargs="+", help="LABEL=FILE.exr, drawn left to right")
    args = ap.parse_args()
    ref = read_image(args.reference)[..., :3]
    pairs = [item.split("=", 1) for item in args.images]
    scale = float(np.percentile(luminance(ref), 99))
    errors = [luminance(read_image(f)[..., :3]) - luminance(ref) for _, f in pairs]
    span = max(float(np.percentile(np.abs(e), 99)) for e in errors)
    fig, axes = plt.subplots(2, len(pairs), figsize=(4.4 * len(pairs), 7.4), squeeze=False, layout="constrained")
    for col, ((label, path), error) in enumerate(zip(pairs, errors)):
        rgb = read_image(path)[..., :3]
        steps = block_step_ratios(rgb, ref)
        axes[0, col].imshow(tonemap(rgb / scale, 0.0, "filmic"))
        axes[0, col].set_title(label, fontsize=11)
        shown = axes[1, col].imshow(error, cmap="RdBu_r", vmin=-span, vmax=span)
        title = "error against the reference\nblock steps " + ", ".join(f"k={k}: {r:.2f}" for k, r in steps.items())
        axes[1, col].set_title(title, fontsize=10)
        for x in range(REGION_PIXELS, error.shape[1], REGION_PIXELS):
            axes[1, col].axvline(x - 0.5, color="0.3", lw=0.4)
        for y in range(REGION_PIXELS, error.shape[0], REGION_PIXELS):
            axes[1, col].axhline(y - 0.5, color="0.3", lw=0.4)
        for ax in axes[:, col]:
            ax.set_xticks([])
            ax.set_yticks([])
    bar = fig.colorbar(shown, ax=axes[1, :].tolist(), orientation="horizontal", shrink=0.7)
    bar.set_label("luminance error (image units); grey lines: the cache's 32-pixel regions")
    atomic_output(args.out, lambda tmp: fig.savefig(tmp, dpi=90, format="png", bbox_inches="tight"))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
