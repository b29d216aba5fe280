"""Mean FLIP (NVIDIA's image-difference measure, flip-evaluator from PyPI) between two HDR
renders as a viewer sees them: both filmic tone-mapped at the same exposure (the callers
take the reference's automatic one) and compared as LDR images. The benchmarks' measure of how an
image looks (bench/aa.py, bench/cache.py) beside their error measures of what it holds."""

from __future__ import annotations

import numpy as np

from patina.render.images import tonemap


def mean_flip(image: np.ndarray, reference: np.ndarray, stops: float) -> float | None:
    """The mean FLIP of `image` against `reference` at `stops` (0: identical; None: no
    flip-evaluator here)."""
    try:
        import flip_evaluator
    except ImportError:
        return None
    ldr = [tonemap(x, stops, "filmic").astype(np.float32) / 255.0 for x in (reference, image)]
    return float(flip_evaluator.evaluate(ldr[0], ldr[1], "LDR", applyMagma=False)[1])
