"""The radiance cache's patches a region wide (docs/radiance-cache.md, "Generations"): of each
render's luminance error against a converged reference, the pixels' RMSE, the sd and the
largest |value| of the error averaged over 16 x 16-pixel squares, and the block steps
(patina.bench.block_steps).
Run from the checkout: python tools/cache_measure/region_patches.py REF.exr LABEL=X.exr ..."""

import sys

import numpy as np

from patina.bench.block_steps import block_step_ratios, luminance
from patina.render.images import read_image

SQUARE = 16  # pixels a side: the patches are about a region (32 pixels) wide


def square_means(error: np.ndarray) -> np.ndarray:
    """`error` averaged over the whole SQUARE x SQUARE squares from the image's corner."""
    h, w = (n - n % SQUARE for n in error.shape)
    return error[:h, :w].reshape(h // SQUARE, SQUARE, w // SQUARE, SQUARE).mean(axis=(1, 3))


ref = read_image(sys.argv[1])[..., :3]
print("image, pixel RMSE, 16 x 16 squares' sd, their max |error|, block steps k = 4 / 8 / 16")
for item in sys.argv[2:]:
    label, path = item.split("=", 1)
    image = read_image(path)[..., :3]
    error = luminance(image.astype(np.float64)) - luminance(ref.astype(np.float64))
    squares = square_means(error)
    steps = " / ".join(f"{v:.2f}" for v in block_step_ratios(image, ref).values())
    rmse = float(np.sqrt(np.mean(error**2)))
    print(f"{label}, {rmse:.4f}, {float(squares.std()):.4f}, {float(np.abs(squares).max()):.4f}, {steps}")
