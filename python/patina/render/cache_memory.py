"""The radiance cache's memory, estimated before a render starts (docs/radiance-cache.md,
"Regions"): what `patina render` states before any work.

The cache keeps the regions no tile needs at the moment within a budget
(`_core.cache_region_budget_bytes`, 256 MB), dropping the least recently used ones and
making room before each region is built. What the budget cannot bound is the regions the
tiles in flight need: each thread holds the regions under the tile it renders (and, for
`cache`, within a block of it) and may be building another, and a region's points are set
by the settings and the scene, not by the budget. At R texels a side a cache point keeps
about CACHE_BYTES_PER_TEXEL x R^2 bytes, and a region of P x P pixels may hold a cache
point for every block of K x K pixels (more only where one block sees several surfaces),
so a region may weigh (P / K)^2 of them."""

from __future__ import annotations

import math

from patina.native import _core
from patina.render.run import render_threads
from patina.scene.types import Scene

# A cache point's kept arrays per texel of its hemisphere: radiance (3 floats), distance,
# kind, and for a hit its surfel with the outline points reprojection reads. Measured:
# 76 bytes at R = 64 over the 10,000-odd cache points of cache-room at --cache-block 1.
CACHE_BYTES_PER_TEXEL = 80
CACHE_INTEGRATORS = ("cache", "cache-guided")


def cache_point_bytes(resolution: int) -> int:
    return CACHE_BYTES_PER_TEXEL * resolution * resolution


# `cache` keeps each pre-pass query's reconstructed hemisphere with its region: RGB floats a texel
HEMISPHERE_BYTES_PER_TEXEL = 12


def cache_region_bytes(resolution: int, block: int, hemispheres: bool = False) -> int:
    """A region's points, at one cache point a block, and with `hemispheres` a reconstruction
    a block too."""
    per_texel = CACHE_BYTES_PER_TEXEL + (HEMISPHERE_BYTES_PER_TEXEL if hemispheres else 0)
    return math.ceil(_core.cache_region_pixels / block) ** 2 * per_texel * resolution * resolution


def regions_held(scene: Scene) -> int:
    """The regions a tile's item may hold: those under the tile and, for `cache`, its margin
    of a block, whose hemispheres its pixels may take (RenderJob::cache_regions_near)."""
    margin = scene.render.cache.block if scene.render.integrator == "cache" else 0
    size, tile = _core.cache_region_pixels, _core.tile_pixels[scene.render.aa]
    across = max(
        (x0 + tile + margin - 1) // size - max(x0 - margin, 0) // size + 1 for x0 in range(0, size * tile, tile)
    )
    return across * across


def cache_memory(scene: Scene, threads: int) -> int:
    """Bytes the radiance cache may take at most: the kept regions' budget and, for each of
    `threads` (0: one a core), the regions its item holds and one being built (0 without a
    cache)."""
    if scene.render.integrator not in CACHE_INTEGRATORS:
        return 0
    cache = scene.render.cache
    region = cache_region_bytes(cache.resolution, cache.block, scene.render.integrator == "cache")
    per_thread = (regions_held(scene) + 1) * region
    return _core.cache_region_budget_bytes + render_threads(threads) * per_thread


def cache_memory_notice(scene: Scene, threads: int) -> str | None:
    """One line for settings whose regions outgrow the budget (large R, small blocks), else None."""
    need = cache_memory(scene, threads)
    budget = _core.cache_region_budget_bytes
    if need <= 2 * budget:
        return None
    cache = scene.render.cache
    pixels = _core.cache_region_pixels
    return (
        f"radiance cache: may take up to {need / 2**30:.1f} GiB: at resolution {cache.resolution} a cache point "
        f"keeps about {cache_point_bytes(cache.resolution) / 2**20:.2f} MB and at block {cache.block} a "
        f"{pixels}x{pixels}-pixel region up to {math.ceil(pixels / cache.block) ** 2} of them; a thread "
        f"holds up to {regions_held(scene)} regions and may build another ({render_threads(threads)} threads here), "
        "beyond the "
        f"{budget / 2**20:.0f} MB the cache keeps between tiles (a larger --cache-block or a smaller "
        "--cache-resolution takes less)"
    )
