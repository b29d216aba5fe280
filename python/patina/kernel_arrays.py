"""The arrays the native kernels take: C-contiguous float32 (nanobind refuses other dtypes and
strided views rather than copying them)."""

from __future__ import annotations

import numpy as np


def as_float32(values: np.ndarray) -> np.ndarray:
    """`values` as a C-contiguous float32 array (itself when it already is one)."""
    return np.ascontiguousarray(values, dtype=np.float32)
