"""Structured artefacts in an image's error (issue 31): the mean step of the error across the
boundaries of a k x k grid of pixels over its mean step elsewhere. The radiance cache shares
a reconstructed hemisphere between the pixels of a block and a cache point's noise between
the points that reuse it; where that sharing follows the block grid, the error jumps at the
grid's lines and the image shows a mosaic even when its error figure is good. Noise that is
independent from pixel to pixel steps as much on the lines as off them: a ratio of 1."""

from __future__ import annotations

import numpy as np

BLOCK_SIZES = (4, 8, 16)


def luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


def block_step_ratio(error: np.ndarray, k: int) -> float:
    """Mean |step| of `error` (h, w) between neighbouring pixels that a k x k grid from the
    image's corner separates, over the mean |step| between those it does not."""
    dx, dy = np.abs(np.diff(error, axis=1)), np.abs(np.diff(error, axis=0))
    across_x = np.arange(1, error.shape[1]) % k == 0  # step x-1 -> x crosses a grid line
    across_y = np.arange(1, error.shape[0]) % k == 0
    on = np.concatenate([dx[:, across_x].ravel(), dy[across_y, :].ravel()])
    if on.size == 0:
        raise ValueError(f"a {error.shape[1]}x{error.shape[0]} image has no line of a {k}-pixel grid inside it")
    off = np.concatenate([dx[:, ~across_x].ravel(), dy[~across_y, :].ravel()])
    return float(on.mean() / max(off.mean(), 1e-30))


def block_step_ratios(image: np.ndarray, reference: np.ndarray) -> dict[int, float]:
    """block_step_ratio of the luminance error of `image` against `reference` (RGB), per k
    whose grid has a line inside the image."""
    error = luminance(np.asarray(image, np.float64)) - luminance(np.asarray(reference, np.float64))
    return {k: block_step_ratio(error, k) for k in BLOCK_SIZES if k < max(error.shape)}
