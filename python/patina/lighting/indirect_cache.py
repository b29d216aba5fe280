"""Indirect illuminance on sensors from the radiance cache (issue 32; docs/lighting.md).

A sensor is a point with a normal and a cosine response, and the indirect light reaching it
is smooth over a grid: the radiance cache's case. Cache points are built at some of the
sensors (`_core.sensor_cache_points`, render/cache/sensor_cache_points_impl.h: the cache's
R x R hemisphere of jittered texel paths, integrated against the sensor's cosine, and the
texels' harmonic mean hit distance R_A); every sensor then gathers from the cache points near
it by the cache's error criterion (render/cache/error_criterion.h),

    e(A, B) = |B - A| / R_A + sqrt(1 - n_A . n_B),

each cache point with e <= `bound` weighted by 1 - e / bound. Placement goes in rounds as the
cache's does (render/cache/radiance_cache_impl.h): each round, of the sensors no built cache
point serves, the first in each cube of side bound x the built points' median R_A becomes
one; the first round builds a pilot spread over the sensors (one in each cube of 1/8 of their
bounding box's diagonal), the last makes every sensor still unserved a cache point. A
sensor's radius in e is the lesser of R_A and that of the cache point nearest it, so that
sensors by a wall do not gather the open room's light.

Its bias is the gathering's: docs/lighting.md gives it measured against a converged path
estimate on the bundled office.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from patina.native import _core

BOUND = 0.5  # the error criterion's bound (docs/lighting.md: the bias it gives)
RESOLUTION = 16  # a cache point's hemisphere: R x R texel paths
ROUNDS = 6
PILOT_SPACING = 1 / 8  # of the sensors' bounding-box diagonal: the first round's cache points


@dataclass(frozen=True)
class CacheSettings:
    """What the sensor cache takes from the scene and the command line."""

    max_depth: int  # the scene file's render.max_depth (patina.render.illuminance.sensor_depth)
    seed: int = 0
    resolution: int = RESOLUTION
    bound: float = BOUND
    width: int = 0
    threads: int = 0


@dataclass(frozen=True)
class CachedIndirect:
    """The sensors' indirect lux and the cache points they gathered from (sensor indices)."""

    lux: np.ndarray
    cache_points: np.ndarray


@dataclass
class _Built:
    """The cache points built so far: their sensors, lux and reuse radii."""

    sensors: list[int]
    lux: list[float]
    radius: list[float]

    def errors(self, points: np.ndarray, normals: np.ndarray, at: np.ndarray) -> np.ndarray:
        """e(A, B) for every built A (rows) and the sensors `at` (columns), the radius the
        lesser of A's and that of the cache point nearest B: a sensor by a wall, whose nearest
        cache point sees the wall close, does not gather from the open room's points, whose
        large R_A would reach it (the office's 0.25 m grid, 16 x 16 texels, bound 0.3: mean
        -1.2 % and rms 3.4 % against the paths with R_A alone, +0.3 % and 2.5 % with the lesser)."""
        idx = np.asarray(self.sensors)
        radius = np.asarray(self.radius, np.float32)
        # float32, coordinate by coordinate: no matrix product (and its threads) for 3 columns
        squared = np.zeros((len(idx), len(at)), np.float32)
        cosine = np.zeros_like(squared)
        for k in range(3):
            squared += np.square(points[idx, k, None].astype(np.float32) - points[at, k].astype(np.float32))
            cosine += normals[idx, k, None].astype(np.float32) * normals[at, k].astype(np.float32)
        dist = np.sqrt(squared)
        spread = np.sqrt(np.clip(1.0 - cosine, 0.0, None))
        nearest = radius[np.argmin(squared, axis=0)]
        return dist / np.minimum(radius[:, None], nearest[None, :]) + spread

    def least_errors(self, points: np.ndarray, normals: np.ndarray, at: np.ndarray) -> np.ndarray:
        """The least e(A, B) over the built points of each sensor of `at`."""
        return np.concatenate([self.errors(points, normals, at[part]).min(axis=0) for part in _chunks(len(at))])

    def gather(self, points: np.ndarray, normals: np.ndarray, bound: float) -> np.ndarray:
        """Each sensor's lux: the built points within the bound, weighted by 1 - e / bound."""
        lux = np.asarray(self.lux)[:, None]
        out = []
        for at in _chunks(len(points)):
            errors = self.errors(points, normals, at)
            weights = np.clip(1.0 - errors / bound, 0.0, None)
            # a later round's point may have shrunk a served sensor's radius: its least-error
            # cache point serves it then
            lonely = weights.sum(axis=0) == 0
            weights[np.argmin(errors[:, lonely], axis=0), np.flatnonzero(lonely)] = 1.0
            out.append((lux * weights).sum(axis=0) / weights.sum(axis=0))
        return np.concatenate(out)


def _chunks(n: int, size: int = 2048) -> list[np.ndarray]:
    """Sensor indices in chunks (the error matrix of a chunk: built points x size)."""
    return [np.arange(b, min(b + size, n)) for b in range(0, n, size)]


def _build(prepared_core, points, normals, sensors: list[int], settings: CacheSettings, built: _Built) -> None:
    if not sensors:
        return
    pts = np.ascontiguousarray(points[sensors], np.float32)
    nrm = np.ascontiguousarray(normals[sensors], np.float32)
    lux, radius = _core.sensor_cache_points(
        prepared_core,
        pts,
        nrm,
        settings.resolution,
        settings.seed + len(built.sensors),  # each round's points draw streams of their own
        settings.width,
        settings.threads,
        settings.max_depth,
    )
    built.sensors += sensors
    built.lux += [float(v) for v in lux]
    built.radius += [float(r) for r in radius]


def _first_in_cells(points: np.ndarray, normals: np.ndarray, at: np.ndarray, size: float) -> list[int]:
    """Of the sensors `at`, in order, the first in each cube of side `size` (and of each
    normal, to a quarter): new cache points about `size` apart, as the cache's rule of no two
    of a round within the bound of each other places them, without its loop over pairs."""
    cells = np.floor(points[at] / max(size, 1e-6)).astype(np.int64)
    facing = np.round(normals[at] * 4).astype(np.int64)
    _, first = np.unique(np.concatenate([cells, facing], axis=1), axis=0, return_index=True)
    return sorted(int(at[i]) for i in first)


def _pilot(points: np.ndarray, normals: np.ndarray) -> list[int]:
    """The first round's cache points: the first sensor in each cube of PILOT_SPACING of the
    sensors' bounding-box diagonal (spread over the grid, so that the next round's radius
    estimate is not one corner's)."""
    spacing = PILOT_SPACING * float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
    return _first_in_cells(points, normals, np.arange(len(points)), spacing)


def cached_indirect(prepared_core, points: np.ndarray, normals: np.ndarray, settings: CacheSettings) -> CachedIndirect:
    """The indirect illuminance (lux) at sensors (points, unit normals: (n, 3)) from cache
    points placed among them and gathered by the error criterion."""
    points = np.asarray(points, np.float64)
    normals = np.asarray(normals, np.float64)
    n = len(points)
    built = _Built([], [], [])
    if n == 0:
        return CachedIndirect(np.zeros(0), np.zeros(0, int))
    _build(prepared_core, points, normals, _pilot(points, normals), settings, built)
    unserved = np.arange(n)
    for round_ in range(1, ROUNDS):
        # a sensor served stays so (but for a later point's smaller radius: gather's fallback)
        unserved = unserved[built.least_errors(points, normals, unserved) > settings.bound]
        if len(unserved) == 0:
            break
        finite = [r for r in built.radius if np.isfinite(r)]
        estimate = float(np.median(finite)) if finite else np.inf
        if round_ < ROUNDS - 1:
            new_points = _first_in_cells(points, normals, unserved, settings.bound * estimate)
        else:
            new_points = [int(i) for i in unserved]
        _build(prepared_core, points, normals, new_points, settings, built)
    return CachedIndirect(built.gather(points, normals, settings.bound), np.asarray(built.sensors))
