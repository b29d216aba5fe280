"""Scattered measurements onto an irregular tensor grid.

Goniophotometers often sample angles that do not form a tensor grid. Each axis gets
its knots from the data's own density (the measured values themselves when there are
few, quantiles of the measured angles otherwise), the grid values come from linear
interpolation over a Delaunay triangulation of the data (nearest neighbour outside its
hull), and the error is measured by interpolating the grid back at every measured
point. scipy does the triangulation.

Isotropic data (theta_i, theta_o, phi_d) are resampled with Helmholtz reciprocity: each
sample also stands for its swapped pair (theta_o, theta_i, phi_d), so both halves of the
grid come from the same measurements (where both orders were measured, their mean). A
measurement's incidence angles are usually few and its viewing angles many, so without
the swap the theta_i and theta_o axes were interpolated from different data and the
table was far from reciprocal (97-200 % at the 95th percentile on a 1439-point file).

Data that span no volume (one row, points on a line or a plane of the angle space) cannot
be triangulated: CannotResample says so, before scipy is asked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

MAX_KNOTS = {"theta": 24, "phi": 36}
# The resampled grid's values (knots x channels) at most: a scattered file of 4 rows and
# 5000 wavelength columns otherwise asked for a 24 x 24 x 36 x 5000 grid in float64, several
# times over (7.7 GB). Up to 404 channels fit the largest grid; more are refused up front.
MAX_GRID_VALUES = 1 << 23


class CannotResample(ValueError):
    """Scattered data that cannot be resampled: points that span no volume of the angle
    space, or more values than MAX_GRID_VALUES (the reader adds the file)."""


@dataclass
class ResampleError:
    points: int
    grid: tuple[int, ...]
    relative_median: float
    relative_p95: float
    relative_max: float

    def describe(self) -> str:
        return (
            f"resampled from {self.points} scattered points onto a {' x '.join(map(str, self.grid))} grid; "
            f"relative error at the measured points: median {self.relative_median:.3g}, "
            f"95% {self.relative_p95:.3g}, max {self.relative_max:.3g}"
        )


# Angles closer than this are one knot: a Zemax file's scatter directions turned into
# (theta_i, theta_o, phi_d) give 20 deg and 20 deg + 1e-14 as two values, which float32 (the
# table's) cannot tell apart -- the table then refused its own axis as not increasing.
KNOT_TOLERANCE = 1e-6  # radians, far below any goniometer's resolution


def _distinct(x: np.ndarray) -> np.ndarray:
    """x's values sorted, each within KNOT_TOLERANCE of the one before dropped."""
    values = np.unique(x)
    keep = np.concatenate([[True], np.diff(values) > KNOT_TOLERANCE]) if values.size else values.astype(bool)
    return values[keep]


def choose_knots(x: np.ndarray, max_knots: int) -> np.ndarray:
    """Strictly increasing knots spanning x: its distinct values, or its quantiles if too many."""
    distinct = _distinct(x)
    if distinct.size <= max_knots:
        knots = distinct
    else:
        knots = _distinct(np.quantile(x, np.linspace(0.0, 1.0, max_knots)))
    if knots.size < 2:
        knots = np.array([knots[0], knots[0] + 1e-3])
    return knots


def _check_spans_a_volume(points: np.ndarray, names: list[str]) -> None:
    """CannotResample unless the distinct points span all D dimensions (D + 1 of them at least,
    not on one line or plane): what a Delaunay triangulation needs."""
    count, dims = points.shape
    if count < dims + 1:
        raise CannotResample(
            f"{count} distinct scattered point{'s' if count != 1 else ''}: resampling onto a grid needs at least "
            f"{dims + 1} that are not on one plane of ({', '.join(names)})"
        )
    span = points.max(axis=0) - points.min(axis=0)
    flat = [n for n, w in zip(names, span) if w <= 1e-9]
    if flat:
        raise CannotResample(
            f"every scattered point has the same {', '.join(flat)}: the points span no volume of "
            f"({', '.join(names)}), so they cannot be resampled onto a grid"
        )
    centred = (points - points.mean(axis=0)) / span
    rank = int(np.linalg.matrix_rank(centred, tol=1e-9 * np.sqrt(count)))
    if rank < dims:
        shape = "line" if rank == 1 else "plane"
        raise CannotResample(
            f"the {count} scattered points lie on one {shape} of ({', '.join(names)}): "
            "they span no volume, so they cannot be resampled onto a grid"
        )


def resample(
    coords: np.ndarray, values: np.ndarray, names: list[str]
) -> tuple[list[np.ndarray], np.ndarray, ResampleError]:
    """coords (N, D) angles in radians named `names`, values (N, C) -> (axes, grid (*shape, C), error).

    Raises CannotResample when the points span no volume or the grid would be too large."""
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator, RegularGridInterpolator
    from scipy.spatial import QhullError

    coords = np.asarray(coords, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    samples, sample_values = coords, values
    if names == ["theta_i", "theta_o", "phi_d"]:  # reciprocity: (theta_o, theta_i, phi_d) too
        swapped = coords[:, [1, 0, 2]]
        off = coords[:, 0] != coords[:, 1]
        samples = np.concatenate([coords, swapped[off]])
        sample_values = np.concatenate([values, values[off]])
    # repeated measurements of one direction pair: their mean
    unique, inverse = np.unique(samples, axis=0, return_inverse=True)
    counts = np.bincount(inverse.ravel(), minlength=len(unique))
    means = np.stack(
        [np.bincount(inverse.ravel(), weights=sample_values[:, c]) for c in range(values.shape[1])], axis=1
    )
    means /= counts[:, None]
    _check_spans_a_volume(unique, names)
    axes = [
        choose_knots(unique[:, d], MAX_KNOTS["phi" if n.startswith("phi") else "theta"]) for d, n in enumerate(names)
    ]
    size = math.prod(a.size for a in axes)
    if size * values.shape[1] > MAX_GRID_VALUES:
        raise CannotResample(
            f"resampling {values.shape[1]} channels onto a {' x '.join(str(a.size) for a in axes)} grid would make "
            f"{size * values.shape[1]} values, more than the {MAX_GRID_VALUES} a resampled table may have"
        )
    mesh = np.meshgrid(*axes, indexing="ij")
    nodes = np.stack([m.ravel() for m in mesh], axis=1)
    try:
        grid = LinearNDInterpolator(unique, means)(nodes)
    except QhullError as e:  # nearly degenerate beyond what the rank test sees
        first = str(e).strip().splitlines()[0] if str(e).strip() else "triangulation failed"
        raise CannotResample(f"the scattered points cannot be triangulated ({first})") from None
    outside = ~np.isfinite(grid).all(axis=1)
    if outside.any():
        grid[outside] = NearestNDInterpolator(unique, means)(nodes[outside])
    shape = tuple(a.size for a in axes)
    grid = grid.reshape(*shape, values.shape[1])
    back = RegularGridInterpolator(axes, grid, bounds_error=False, fill_value=None)(coords)
    floor = max(1e-3 * float(np.median(np.abs(values))), 1e-12)
    rel = np.abs(back - values) / np.maximum(np.abs(values), floor)
    error = ResampleError(
        points=len(coords),
        grid=shape,
        relative_median=float(np.median(rel)),
        relative_p95=float(np.percentile(rel, 95)),
        relative_max=float(rel.max()),
    )
    return axes, grid, error


def relative_error(table_values: np.ndarray, reference: np.ndarray) -> dict[str, float]:
    """A resampled table against its source (the readers' resampling error): the relative
    error per pair, largest over the channels, with a floor of 1e-3 of the median reference
    value so that near-zero values do not dominate; its median, 95th percentile and maximum."""
    floor = max(1e-3 * float(np.median(np.abs(reference))), 1e-12)
    rel = (np.abs(table_values - reference) / np.maximum(np.abs(reference), floor)).max(axis=1)
    return {"median": float(np.median(rel)), "p95": float(np.percentile(rel, 95)), "max": float(rel.max())}
