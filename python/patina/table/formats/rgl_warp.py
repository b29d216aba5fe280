"""The 2-D interpolants and warps an RGL .bsdf file is made of, in double precision.

Each is a (H, W) grid of values over the unit square, bilinear between the nodes,
possibly one grid per combination of parameters (the incident angles phi_i, theta_i and,
for the spectra, the channel), linear between the parameter values. With `warp=True`
the grid is a density: its marginal (rows) and conditional (columns) CDFs of the
bilinear function map the unit square onto itself (`sample`) and back (`invert`), as
in Dupuy & Jakob 2018, section 5, and the Marginal2D of Mitsuba and rgl-epfl/brdf-loader.

Everything works on N points at once (numpy arrays): the reference against which a
native evaluator is checked, and the generator the RGL writer uses.
"""

from __future__ import annotations

import itertools

import numpy as np


def find_interval(size: int, predicate, count: int) -> np.ndarray:
    """For N searches at once: the index i in [0, size - 2] with predicate(i) true and
    predicate(i + 1) false (a monotone predicate; clamped at both ends)."""
    first = np.ones(count, dtype=np.int64)
    left = np.full(count, size - 2, dtype=np.int64)
    while np.any(left > 0):
        active = left > 0
        half = left >> 1
        middle = np.minimum(first + half, size - 1)
        result = predicate(middle) & active
        first = np.where(result, middle + 1, first)
        left = np.where(active, np.where(result, left - (half + 1), half), left)
    return np.clip(first - 1, 0, size - 2)


class Interpolant2D:
    """values: (*param_sizes, H, W); params: the parameter values of each leading axis."""

    def __init__(self, values: np.ndarray, params: list[np.ndarray] | None = None, warp: bool = False) -> None:
        params = params or []
        values = np.asarray(values, dtype=np.float64)
        self.params = [np.asarray(p, dtype=np.float64) for p in params]
        self.param_sizes = [p.size for p in self.params]
        if list(values.shape[:-2]) != self.param_sizes:
            raise ValueError(f"shape {values.shape} does not match parameters {self.param_sizes}")
        self.height, self.width = values.shape[-2:]
        if self.height < 2 or self.width < 2:
            raise ValueError(f"a {self.height} x {self.width} grid: at least 2 x 2 nodes are needed")
        strides, slices = [], 1
        for n in reversed(self.param_sizes):
            strides.append(slices if n > 1 else 0)
            slices *= n
        self.strides = list(reversed(strides))
        data = values.reshape(slices, self.height * self.width)
        self.warp = warp
        if warp:
            rows = data.reshape(slices, self.height, self.width)
            conditional = np.zeros_like(rows)
            conditional[..., 1:] = np.cumsum(0.5 * (rows[..., 1:] + rows[..., :-1]), axis=-1)
            totals = conditional[..., -1]
            marginal = np.zeros((slices, self.height))
            marginal[:, 1:] = np.cumsum(0.5 * (totals[:, 1:] + totals[:, :-1]), axis=-1)
            norm = 1.0 / marginal[:, -1:]
            self.marginal = marginal * norm
            self.conditional = (conditional * norm[:, :, None]).reshape(slices, -1)
            data = data * norm
        self.data = data

    # --- the parameters' corners and weights
    def _corners(self, params: list[np.ndarray], count: int) -> list[tuple[np.ndarray, np.ndarray]]:
        per_dim = []
        for values, stride, p in zip(self.params, self.strides, params):
            if values.size == 1:
                per_dim.append([(np.zeros(count, np.int64), np.ones(count))])
                continue
            index = np.clip(np.searchsorted(values, p, side="right") - 1, 0, values.size - 2)
            p0, p1 = values[index], values[index + 1]
            w1 = np.clip((p - p0) / (p1 - p0), 0.0, 1.0)
            per_dim.append([(index * stride, 1.0 - w1), ((index + 1) * stride, w1)])
        corners = []
        for combo in itertools.product(*per_dim) if per_dim else [()]:
            offset = np.zeros(count, np.int64)
            weight = np.ones(count)
            for o, w in combo:
                offset = offset + o
                weight = weight * w
            corners.append((offset, weight))
        return corners

    @staticmethod
    def _lookup(table: np.ndarray, corners, index: np.ndarray) -> np.ndarray:
        return sum(w * table[s, index] for s, w in corners)

    # --- evaluation
    def _patch(self, pos: np.ndarray, corners) -> tuple[np.ndarray, ...]:
        """For points (N, 2): the node index of their patch, their place in it, and its corners."""
        x = pos[:, 0] * (self.width - 1)
        y = pos[:, 1] * (self.height - 1)
        ix = np.clip(np.floor(x), 0, self.width - 2).astype(np.int64)
        iy = np.clip(np.floor(y), 0, self.height - 2).astype(np.int64)
        i = ix + iy * self.width
        return (i, iy, x - ix, y - iy, *self._corner_values(i, corners))

    def _corner_values(self, i: np.ndarray, corners) -> tuple[np.ndarray, ...]:
        """The data at the four nodes of the patches whose first node is i: v00, v10, v01, v11."""
        return tuple(self._lookup(self.data, corners, i + d) for d in (0, 1, self.width, self.width + 1))

    def eval(self, pos: np.ndarray, params: list[np.ndarray] | None = None) -> np.ndarray:
        """The bilinear value at pos (N, 2) = (x along W, y along H) in [0, 1]^2 (the density if warp)."""
        pos = np.asarray(pos, dtype=np.float64)
        _, _, wx, wy, v00, v10, v01, v11 = self._patch(pos, self._corners(params or [], len(pos)))
        value = (1 - wy) * ((1 - wx) * v00 + wx * v10) + wy * ((1 - wx) * v01 + wx * v11)
        return value * self._density_scale()

    def _density_scale(self) -> float:
        return float((self.width - 1) * (self.height - 1)) if self.warp else 1.0

    def invert(self, pos: np.ndarray, params: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """The uniform sample that `sample` maps onto pos, and the density there."""
        pos = np.asarray(pos, dtype=np.float64)
        n = len(pos)
        corners = self._corners(params, n)
        i, iy, sx, sy, v00, v10, v01, v11 = self._patch(pos, corners)
        c0 = (1 - sy) * v00 + sy * v01
        c1 = (1 - sy) * v10 + sy * v11
        pdf = (1 - sx) * c0 + sx * c1
        ux = sx * (c0 + 0.5 * sx * (c1 - c0))
        ux = (
            ux
            + (1 - sy) * self._lookup(self.conditional, corners, i)
            + sy * self._lookup(self.conditional, corners, i + self.width)
        )
        row = iy * self.width
        r0 = self._lookup(self.conditional, corners, row + self.width - 1)
        r1 = self._lookup(self.conditional, corners, row + 2 * self.width - 1)
        ux = ux / np.maximum((1 - sy) * r0 + sy * r1, 1e-300)
        uy = sy * (r0 + 0.5 * sy * (r1 - r0))
        uy = uy + self._lookup(self.marginal, corners, iy)
        return np.stack([ux, uy], axis=1), pdf * self._density_scale()

    def sample(self, u: np.ndarray, params: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Uniform u (N, 2) in [0, 1]^2 -> a point distributed as the density, and its density."""
        u = np.clip(np.asarray(u, dtype=np.float64), 1e-7, 1 - 1e-7)
        n = len(u)
        corners = self._corners(params, n)
        ux, uy = u[:, 0].copy(), u[:, 1].copy()
        row = find_interval(self.height, lambda k: self._lookup(self.marginal, corners, k) < uy, n)
        uy = uy - self._lookup(self.marginal, corners, row)
        offset = row * self.width
        r0 = self._lookup(self.conditional, corners, offset + self.width - 1)
        r1 = self._lookup(self.conditional, corners, offset + 2 * self.width - 1)
        sy = _solve_linear_density(r0, r1, uy)
        ux = ux * ((1 - sy) * r0 + sy * r1)

        def conditional_at(k: np.ndarray) -> np.ndarray:
            return (1 - sy) * self._lookup(self.conditional, corners, offset + k) + sy * self._lookup(
                self.conditional, corners, offset + self.width + k
            )

        col = find_interval(self.width, lambda k: conditional_at(k) < ux, n)
        ux = ux - conditional_at(col)
        v00, v10, v01, v11 = self._corner_values(offset + col, corners)
        c0 = (1 - sy) * v00 + sy * v01
        c1 = (1 - sy) * v10 + sy * v11
        sx = _solve_linear_density(c0, c1, ux)
        pos = np.stack([(col + sx) / (self.width - 1), (row + sy) / (self.height - 1)], axis=1)
        return pos, ((1 - sx) * c0 + sx * c1) * self._density_scale()


def _solve_linear_density(a: np.ndarray, b: np.ndarray, u: np.ndarray) -> np.ndarray:
    """t in [0, 1] with integral_0^t ((1 - s) a + s b) ds = u: the inverse CDF of a linear density."""
    constant = np.abs(a - b) < 1e-4 * (a + b)
    with np.errstate(invalid="ignore", divide="ignore"):
        root = (a - np.sqrt(np.maximum(a * a - 2.0 * u * (a - b), 0.0))) / (a - b)
        flat = 2.0 * u / (a + b)
    return np.clip(np.where(constant, flat, root), 0.0, 1.0)
