"""Structured artefacts in an image's error (issue 31): the mean step of the error across the
lines of a k x k grid of pixels over its mean step beside them. The radiance cache shares a
reconstructed hemisphere between the pixels of a block and a cache point's noise between the
points that reuse it; where that sharing follows the block grid, the error jumps at the grid's
lines and the image shows a mosaic even when its error figure is good. Noise that is
independent from pixel to pixel steps as much on the lines as beside them: a ratio of 1.

Two things the measure does not count as structure (docs/radiance-cache.md, "The mosaic"):
- **a few outlying pixels**: the error is clipped to its OUTLIER_QUANTILE (the top 0.1 % of
  pixel errors, as relMSE discards them). A highlight the path tracer samples (the room's sun
  in its metal ball: one step 650 times the image's mean step) that lies on a line decided
  the figure by itself: `path` at 16 spp measured 1.26 on the room, `cache` 1.32.
- **noise that differs from place to place**: a line's steps are compared with the parallel
  steps one pixel either side of it, not with the image's mean. A patch of stronger noise
  (the studio's path-traced highlight on its car paint, its RMS error 20 times the cache's
  elsewhere) that straddles a line raised the line's mean step and not the image's:
  `cache` 1.24 on the studio at 16 spp against `path`'s 1.07, the same noise weighing more
  beside the cache's lower error.
A mosaic steps on the line and not beside it, so it still counts in full: the cache with its
blocks' hemispheres on the block grid measures 1.25 to 1.93 at 16 spp, now 1.00 to 1.09."""

from __future__ import annotations

import numpy as np

BLOCK_SIZES = (4, 8, 16)
OUTLIER_QUANTILE = 0.999  # errors beyond this quantile of |error| are clipped to it


def luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


def without_outliers(error: np.ndarray) -> np.ndarray:
    """`error` clipped to +-its OUTLIER_QUANTILE of |error|."""
    bound = float(np.quantile(np.abs(error), OUTLIER_QUANTILE))
    return np.clip(error, -bound, bound)


def line_steps(steps: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Of `steps` (rows of |step| from column j to j + 1), those across the lines of a k-pixel
    grid from the image's corner (j + 1 a multiple of k) and, for each, the mean of the two
    parallel steps beside it (j - 1 and j + 1); lines without a step on both sides are left out."""
    j = np.arange(k - 1, steps.shape[1] - 1, k)
    return steps[:, j].ravel(), (0.5 * (steps[:, j - 1] + steps[:, j + 1])).ravel()


def block_step_ratio(error: np.ndarray, k: int) -> float:
    """Mean |step| of `error` (h, w), its outliers clipped, between neighbouring pixels that a
    k x k grid from the image's corner separates, over the mean |step| beside those lines."""
    error = without_outliers(error)
    across = [line_steps(np.abs(np.diff(error, axis=1)), k), line_steps(np.abs(np.diff(error, axis=0)).T, k)]
    on = np.concatenate([a for a, _ in across])
    if on.size == 0:
        raise ValueError(f"a {error.shape[1]}x{error.shape[0]} image has no line of a {k}-pixel grid inside it")
    beside = np.concatenate([b for _, b in across])
    return float(on.mean() / max(beside.mean(), 1e-30))


def block_step_ratios(image: np.ndarray, reference: np.ndarray) -> dict[int, float]:
    """block_step_ratio of the luminance error of `image` against `reference` (RGB), per k
    whose grid has a line inside the image (with a pixel beyond it)."""
    error = luminance(np.asarray(image, np.float64)) - luminance(np.asarray(reference, np.float64))
    return {k: block_step_ratio(error, k) for k in BLOCK_SIZES if k + 1 < max(error.shape)}
