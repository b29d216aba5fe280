"""Scattered measurements onto an irregular tensor grid.

Goniophotometers often sample angles that do not form a tensor grid. Each axis gets
its knots from the data's own density (the measured values themselves when there are
few, quantiles of the measured angles otherwise), the grid values come from linear
interpolation over a Delaunay triangulation of the data (nearest neighbour outside its
hull), and the error is measured by interpolating the grid back at every measured
point. scipy does the triangulation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MAX_KNOTS = {"theta": 24, "phi": 36}


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


def choose_knots(x: np.ndarray, max_knots: int) -> np.ndarray:
    """Strictly increasing knots spanning x: its distinct values, or its quantiles if too many."""
    distinct = np.unique(x)
    if distinct.size <= max_knots:
        knots = distinct
    else:
        knots = np.unique(np.quantile(x, np.linspace(0.0, 1.0, max_knots)))
    if knots.size < 2:
        knots = np.array([knots[0], knots[0] + 1e-3])
    return knots


def resample(
    coords: np.ndarray, values: np.ndarray, names: list[str]
) -> tuple[list[np.ndarray], np.ndarray, ResampleError]:
    """coords (N, D) angles in radians named `names`, values (N, C) -> (axes, grid (*shape, C), error)."""
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator, RegularGridInterpolator

    coords = np.asarray(coords, dtype=np.float64)
    values = np.asarray(values, dtype=np.float64)
    # repeated measurements of one direction pair: their mean
    unique, inverse = np.unique(coords, axis=0, return_inverse=True)
    counts = np.bincount(inverse.ravel(), minlength=len(unique))
    means = np.stack([np.bincount(inverse.ravel(), weights=values[:, c]) for c in range(values.shape[1])], axis=1)
    means /= counts[:, None]
    axes = [
        choose_knots(unique[:, d], MAX_KNOTS["phi" if n.startswith("phi") else "theta"]) for d, n in enumerate(names)
    ]
    mesh = np.meshgrid(*axes, indexing="ij")
    nodes = np.stack([m.ravel() for m in mesh], axis=1)
    grid = LinearNDInterpolator(unique, means)(nodes)
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
