"""Calculation grids laid out by the standards' rules. Each grid says which rule made it.

Plan coordinates are the scenes' ground plane: x and z in metres, y up (docs/scene.md).
Every rule puts its points at the centres of equal cells, so a cell drawn round each point
tiles the area exactly (patina.lighting.plan draws them so).

- EN 12464-1:2021, clause 5.2 (the same rule as its 2011 edition, after CIE 97 / ISO 30061):
  cell size p = 0.2 x 5^log10(d) m, d the area's longer side (p at most 10 m); the number of
  points along a side is the side over p rounded up, so the cells are at most p; a band of
  0.5 m along the walls is left out of the area unless the task area reaches into it.
- EN 13201-3:2015, clause 6: the field between two consecutive luminaires of a row;
  longitudinally N = 10 points for a spacing S <= 30 m, else the least N with S / N <= 3 m,
  the first D / 2 past the first luminaire; across, three points per lane at the lanes'
  thirds' centres (luminance), and for illuminance points at most 1.5 m apart, at least three,
  over the whole carriageway. Observers 1.5 m high, 60 m before the field, at each lane's
  centre line, looking along the road.
- EN 12193:2018: the sport's grid over the principal area (PA) and the total area (TA), at
  the spacing its Annex A gives for the sport (given by the user), points at cell centres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError

WALL_BAND = 0.5  # m, EN 12464-1's band along the walls
OBSERVER_EYE = 1.5  # m, EN 13201-3's observer height
OBSERVER_DISTANCE = 60.0  # m before the field
MAX_ROAD_STEP = 3.0  # m, longitudinal spacing beyond 30 m luminaire spacing
MAX_ACROSS_STEP = 1.5  # m, transverse spacing of illuminance grids


@dataclass(frozen=True)
class RuleGrid:
    """Sensor points at x (nx,) by z (nz,) (cell centres) at height y, and the rule's name."""

    x: np.ndarray
    z: np.ndarray
    y: float
    rule: str

    @property
    def shape(self) -> tuple[int, int]:
        return len(self.z), len(self.x)

    def points(self) -> np.ndarray:
        """(nz * nx, 3) rows of constant z, as patina.render.illuminance.Grid gives them."""
        zz, xx = np.meshgrid(self.z, self.x, indexing="ij")
        return np.stack([xx.ravel(), np.full(xx.size, self.y), zz.ravel()], axis=1)

    def as_json(self) -> dict:
        return {"rule": self.rule, "x": self.x.tolist(), "z": self.z.tolist(), "height": self.y}


def centres(lo: float, hi: float, n: int) -> np.ndarray:
    """n points at the centres of n equal cells over [lo, hi]."""
    step = (hi - lo) / n
    return lo + step * (np.arange(n) + 0.5)


def en12464_cell(d: float) -> float:
    """EN 12464-1's largest cell size (m) for an area whose longer side is d metres."""
    return min(0.2 * 5 ** math.log10(d), 10.0)


def en12464_grid(
    x0: float, z0: float, x1: float, z1: float, height: float, wall_band: bool = False, where: str = "area"
) -> RuleGrid:
    """An EN 12464-1 grid over the rectangle; `wall_band`: the rectangle is a room's inside
    and its 0.5 m band along the walls is left out first."""
    if wall_band:
        x0, z0, x1, z1 = x0 + WALL_BAND, z0 + WALL_BAND, x1 - WALL_BAND, z1 - WALL_BAND
    if not (x1 > x0 and z1 > z0):
        raise FormatError("command line", where, "the area is empty (or narrower than its wall bands)")
    d = max(x1 - x0, z1 - z0)
    p = en12464_cell(d)
    nx, nz = math.ceil((x1 - x0) / p - 1e-9), math.ceil((z1 - z0) / p - 1e-9)
    rule = f"EN 12464-1 5.2: d = {d:g} m, p <= {p:.3g} m, {nx} x {nz} points at cell centres"
    if wall_band:
        rule += f", {WALL_BAND:g} m wall band left out"
    return RuleGrid(centres(x0, x1, nx), centres(z0, z1, nz), height, rule)


def en13201_points_along(spacing: float) -> int:
    """EN 13201-3's N: 10 points for a spacing up to 30 m, else the least with S / N <= 3 m."""
    return 10 if spacing <= 30 else math.ceil(spacing / MAX_ROAD_STEP - 1e-9)


@dataclass(frozen=True)
class Road:
    """A straight carriageway along +z: its kerb at x = x0, `lanes` lanes of `lane_width`
    towards +x; a luminaire row's consecutive luminaires at z = z0 and z0 + spacing."""

    x0: float
    lanes: int
    lane_width: float
    z0: float
    spacing: float

    @property
    def width(self) -> float:
        return self.lanes * self.lane_width

    def lane_centres(self) -> np.ndarray:
        return self.x0 + self.lane_width * (np.arange(self.lanes) + 0.5)

    def along(self) -> np.ndarray:
        return centres(self.z0, self.z0 + self.spacing, en13201_points_along(self.spacing))

    def luminance_grid(self) -> RuleGrid:
        """Three points across each lane, N along the field, on the road surface."""
        x = np.concatenate(
            [centres(self.x0 + i * self.lane_width, self.x0 + (i + 1) * self.lane_width, 3) for i in range(self.lanes)]
        )
        n = en13201_points_along(self.spacing)
        rule = f"EN 13201-3 6.2: field S = {self.spacing:g} m, N = {n} along, 3 per lane x {self.lanes} lanes"
        return RuleGrid(x, self.along(), 0.0, rule)

    def illuminance_grid(self) -> RuleGrid:
        """Points at most 1.5 m apart, at least three, across the carriageway; N along."""
        n_across = max(3, math.ceil(self.width / MAX_ACROSS_STEP - 1e-9))
        n = en13201_points_along(self.spacing)
        rule = f"EN 13201-3 6.3: field S = {self.spacing:g} m, N = {n} along, {n_across} across"
        return RuleGrid(centres(self.x0, self.x0 + self.width, n_across), self.along(), 0.0, rule)

    def observers(self) -> np.ndarray:
        """(lanes, 3): eyes 1.5 m high, 60 m before the field, on each lane's centre line."""
        c = self.lane_centres()
        return np.stack([c, np.full_like(c, OBSERVER_EYE), np.full_like(c, self.z0 - OBSERVER_DISTANCE)], axis=1)


def en12193_grids(
    length: float, width: float, spacing: float, margin: float, height: float = 0.0
) -> tuple[RuleGrid, RuleGrid]:
    """The principal area (length x width, centred on the origin, length along z) and the
    total area (with `margin` round it) at the sport's nominal spacing, points at cell centres."""
    grids = []
    for name, ex in (("PA", 0.0), ("TA", margin)):
        lx, lz = width + 2 * ex, length + 2 * ex
        nx, nz = max(1, math.ceil(lx / spacing - 1e-9)), max(1, math.ceil(lz / spacing - 1e-9))
        rule = f"EN 12193 {name}: {lz:g} x {lx:g} m at <= {spacing:g} m, {nx} x {nz} points at cell centres"
        grids.append(RuleGrid(centres(-lx / 2, lx / 2, nx), centres(-lz / 2, lz / 2, nz), height, rule))
    return grids[0], grids[1]
