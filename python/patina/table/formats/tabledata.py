"""The in-memory form every importer produces before it becomes a native table."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from patina.native import _core


@dataclass
class BadValues:
    """Values a reader found unusable (NaN, infinite, beyond float32) when asked to report
    them rather than refuse the file (patina validate): how many, the first few with their
    place in the file, and (for a grid) which grid points they were at. Those points are
    masked as missing in the table so that every other check can still run."""

    count: int = 0
    places: list[dict[str, Any]] = field(default_factory=list)  # {"where": "byte N" / "line N", ...}
    points: np.ndarray | None = None  # bool, the grid's shape; None when the grid was resampled

    FIRST = 10  # places kept

    def add(self, place: dict[str, Any]) -> None:
        self.count += 1
        if len(self.places) < self.FIRST:
            self.places.append(place)


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
    bad: BadValues | None = None  # set only by a reader asked to report bad values


def table_from_data(data: TableData) -> _core.Table:
    """Turns an importer's TableData into a native (checked, immutable) table."""
    channels = int(data.values.shape[-1])
    symmetry = 0
    if "reciprocity" in data.symmetry:
        symmetry |= _core.SYM_RECIPROCITY
    if "phi_mirror" in data.symmetry:
        symmetry |= _core.SYM_PHI_MIRROR
    valid = None if data.mask is None else np.ascontiguousarray(data.mask, dtype=np.uint8)
    return _core.Table.from_arrays(
        data.parametrization,
        [np.ascontiguousarray(a, dtype=np.float32) for a in data.axes],
        np.ascontiguousarray(data.values, dtype=np.float32).reshape(-1),
        channels,
        data.channel_kind,
        None if data.wavelengths is None else np.ascontiguousarray(data.wavelengths, dtype=np.float32),
        valid,
        symmetry,
        data.units,
        data.provenance,
    )
