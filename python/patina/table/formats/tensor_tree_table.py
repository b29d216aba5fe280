"""Tensor trees (`tensor_tree.py`) resampled onto a Patina table, with the error of that step.

A tree is piecewise constant on cells of the Shirley-Chiu squares; a Patina table is
linear between its knots. The knots are regular in angle (TensorTree3: an isotropic
(theta_i, theta_o, phi_d) grid; TensorTree4: an anisotropic one), each value is the tree's
at the knot, and the difference of the table's interpolation to the tree at random pairs
is written into the provenance.
"""

from __future__ import annotations

import numpy as np

from patina.table.angles import angles_to_directions
from patina.table.formats.resample import relative_error
from patina.table.formats.tabledata import TableData
from patina.table.formats.tensor_tree import TensorTree, tree_coordinates

ERROR_PAIRS = 8192
# knots (degrees): fine enough for the 2^5-2^6 cells per side genBSDF writes, small enough to fit
ISOTROPIC_KNOTS = (np.arange(0, 88, 3.0), np.arange(0, 90, 2.0), np.arange(0, 181, 5.0))
ANISOTROPIC_KNOTS = (np.arange(0, 86, 5.0), np.arange(0, 361, 15.0), np.arange(0, 89, 3.0), np.arange(0, 361, 7.5))


def _pairs(dims: int, angles: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """(wi, wo) for angle arrays in radians: (theta_i, theta_o, phi_d) or (theta_i, phi_i, theta_o, phi_o)."""
    if dims == 3:
        ti, to, pd = angles
        return angles_to_directions(ti, np.zeros_like(ti)), angles_to_directions(to, pd)
    ti, pi, to, po = angles
    return angles_to_directions(ti, pi), angles_to_directions(to, po)


def _evaluate(trees: list[TensorTree], wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    position = tree_coordinates(trees[0].dims, wi, wo)
    return np.stack([t.lookup(position) for t in trees], axis=-1)


def tree_table(trees: list[TensorTree], kind: str, description: str) -> TableData:
    """The trees (one a channel, all of one rank) as a table; `description` opens the provenance."""
    dims = trees[0].dims
    axes = [np.radians(k) for k in (ISOTROPIC_KNOTS if dims == 3 else ANISOTROPIC_KNOTS)]
    mesh = [m.ravel() for m in np.meshgrid(*axes, indexing="ij")]
    values = _evaluate(trees, *_pairs(dims, mesh)).reshape(*(a.size for a in axes), len(trees))
    median, p95 = _resampling_error(trees, axes, values)
    grid = " x ".join(str(a.size) for a in axes)
    notes = [
        description,
        f"tree cells onto an {'isotropic' if dims == 3 else 'anisotropic'} {grid} grid; relative difference "
        f"to the tree at {ERROR_PAIRS} pairs: median {median:.3g}, 95% {p95:.3g}",
    ]
    return TableData(
        parametrization="isotropic" if dims == 3 else "anisotropic",
        axes=axes,
        values=values.astype(np.float32),
        channel_kind=kind,
        provenance="; ".join(notes),
    )


def _resampling_error(trees: list[TensorTree], axes: list[np.ndarray], values: np.ndarray) -> tuple[float, float]:
    """Median and 95th percentile of the table's linear interpolation against the tree."""
    from scipy.interpolate import RegularGridInterpolator

    rng = np.random.default_rng(29)
    dims = trees[0].dims
    if dims == 3:  # both signs of phi_d: the tree may not be mirror-symmetric, the table is
        signed = rng.uniform(-np.pi, np.pi, ERROR_PAIRS)
        angles = [rng.uniform(0, axes[0][-1], ERROR_PAIRS), rng.uniform(0, axes[1][-1], ERROR_PAIRS), signed]
        at = np.stack([angles[0], angles[1], np.abs(signed)], axis=1)
    else:
        angles = [rng.uniform(0, a[-1], ERROR_PAIRS) for a in axes]
        at = np.stack(angles, axis=1)
    want = _evaluate(trees, *_pairs(dims, angles))
    got = RegularGridInterpolator(axes, values)(at)
    err = relative_error(got, want)
    return err["median"], err["p95"]
