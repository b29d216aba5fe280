"""The in-memory form every importer produces before it becomes a native table."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class TableData:
    """A BRDF on a tensor grid with irregular, strictly increasing axes.

    values has shape (*[len(a) for a in axes], channels), C order, float32,
    in `units` (normally 1/sr). mask, if given, has the grid's shape and is
    False where the measurement is missing.
    """

    parametrization: str
    axes: list[np.ndarray]
    values: np.ndarray
    channel_kind: str
    wavelengths: np.ndarray | None = None
    units: str = "1/sr"
    provenance: str = ""
    mask: np.ndarray | None = None
    symmetry: set[str] = field(default_factory=set)
