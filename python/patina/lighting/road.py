"""Road lighting figures of EN 13201-3 from a scene's luminaires and an r-table.

Luminance at a road point P seen by an observer O (the r-table's 1 degree observation angle,
EN 13201-3 7.2): L = MF x sum over luminaires of I(towards P) r(beta, tan gamma) / H^2, where
gamma is the light's incidence at P from the vertical, H the luminaire's height above P, and
beta the angle between the vertical plane of observation (O to P, continued) and the
vertical plane of incidence (P to the luminaire): beta = 0 when the luminaire stands beyond
P on the observer's line of sight, where a road surface shines most. Shadows: one ray per
luminaire, as for illuminance (patina.lighting.direct).

Figures: L_av and U0 = L_min / L_av over the luminance grid, U_l = L_min / L_max along each
lane's centre line for that lane's observer (the worst observer is reported); TI (EN 13201-3
7.5): the veiling luminance L_v = 9.86 sum E_k / theta_k^2 (theta in degrees, E on the
plane normal to the line of sight at the eye, the line of sight 1 degree below the horizontal
along the road) of the luminaires ahead below a 20 degree screening plane and within 500 m,
TI = 65 L_v / L_av^0.8 % (L_av <= 5 cd/m^2) or 95 L_v / L_av^1.05 % (above), with the new
installation's flux (MF = 1), the observer moved over one spacing in the grid's steps from
where the field's first luminaire meets the screening plane, the largest TI reported; EIR
(R_EI): the mean horizontal illuminance on a strip just outside each edge over that on the
strip just inside, strips as wide as the least of 5 m, half the carriageway and the verge
given, the worse side reported.

The illuminance figures (E_av, E_min, U0_E of the C and P classes, EIR) take the
interreflections when the caller gives a way to compute them (`interreflected`: the project's
"indirect", patina.lighting.calculation); the luminance stays the r-table's direct sum, the
standard's method (the r-table is the road's reflection of light arriving from the luminaires).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError
from patina.lighting.direct import PlacedSource, arrivals, direct_illuminance
from patina.lighting.grids import OBSERVER_EYE, Road, centres, en13201_points_along
from patina.lighting.rtable import RTable
from patina.lighting.sensors import Sensors

SIGHT_DOWN_DEG = 1.0  # the line of sight's angle below the horizontal
SCREENING_DEG = 20.0  # the car roof's cut-off above the line of sight
TI_REACH = 500.0  # m ahead
VEILING_K = 9.86  # EN 13201-3's constant for an observer aged 23
EIR_MAX_STRIP = 5.0  # m

# horizontal sensor points (n, 3) -> their interreflected lux (n,), unmaintained
Interreflected = Callable[[np.ndarray], np.ndarray]


@dataclass
class RoadResult:
    luminance: np.ndarray  # (observers, nz, nx) cd/m^2 on the luminance grid
    l_av: float
    u0: float
    ul: float
    ti: float
    eir: float | None
    e_av: float  # mean horizontal illuminance (lx) over the illuminance grid
    e_min: float
    u0_e: float
    illuminance: np.ndarray  # (nz, nx) lux on the illuminance grid

    def figures(self) -> dict[str, float | None]:
        return {
            "L_av": self.l_av,
            "U0": self.u0,
            "Ul": self.ul,
            "TI": self.ti,
            "EIR": self.eir,
            "E_av": self.e_av,
            "E_min": self.e_min,
            "U0_E": self.u0_e,
        }


def road_luminance(
    sources: list[PlacedSource],
    points: np.ndarray,
    observer: np.ndarray,
    table: RTable,
    occluder=None,
    offset: float = 1e-4,
) -> np.ndarray:
    """cd/m^2 at road points (n, 3) for one observer, unmaintained (MF = 1)."""
    a = arrivals(sources, points, occluder, offset)
    view = points - observer[None, :]  # the observer's line to each point, continued beyond it
    view_h = np.stack([view[:, 0], view[:, 2]], axis=1)
    out = np.zeros(len(points))
    for i, src in enumerate(sources):
        height = src.position[1] - points[:, 1]
        to_lum_h = np.stack([src.position[0] - points[:, 0], src.position[2] - points[:, 2]], axis=1)
        horizontal = np.linalg.norm(to_lum_h, axis=1)
        tan_gamma = horizontal / np.maximum(height, 1e-9)
        cos_beta = np.einsum("ij,ij->i", view_h, to_lum_h) / np.maximum(
            np.linalg.norm(view_h, axis=1) * horizontal, 1e-12
        )
        beta = np.degrees(np.arccos(np.clip(cos_beta, -1, 1)))
        lit = (a.candela[i] > 0) & (height > 0)
        out[lit] += a.candela[i, lit] * table(beta[lit], tan_gamma[lit]) / height[lit] ** 2
    return out


def veiling_luminance(sources: list[PlacedSource], eye: np.ndarray, occluder=None, offset: float = 1e-4) -> float:
    """EN 13201-3's L_v (cd/m^2) at an eye looking along +z, 1 degree down."""
    down = math.radians(SIGHT_DOWN_DEG)
    sight = np.array([0.0, -math.sin(down), math.cos(down)])
    a = arrivals(sources, eye[None, :], occluder, offset)
    total = 0.0
    for i, src in enumerate(sources):
        u = a.towards[i, 0]
        ahead = src.position[2] - eye[2]
        elevation = math.degrees(math.asin(np.clip(u[1], -1.0, 1.0)))  # above the horizontal
        if not (0 < ahead <= TI_REACH) or elevation >= SCREENING_DEG or a.candela[i, 0] <= 0:
            continue
        cos_theta = float(np.clip(u @ sight, -1.0, 1.0))
        theta = math.degrees(math.acos(cos_theta))  # from the line of sight
        if theta > 0:
            total += VEILING_K * (a.candela[i, 0] * cos_theta / a.d2[i, 0]) / theta**2
    return total


def threshold_increment(l_v: float, l_av: float) -> float:
    """TI in percent (EN 13201-3 7.5)."""
    if l_av <= 0:
        return math.inf
    return 65 * l_v / l_av**0.8 if l_av <= 5 else 95 * l_v / l_av**1.05


def horizontal_illuminance(
    sources: list[PlacedSource], points: np.ndarray, occluder, offset: float, interreflected: Interreflected | None
) -> np.ndarray:
    """Lux on horizontal sensors at `points`: the exact direct sum, plus the interreflections
    when `interreflected` is given; unmaintained (MF = 1)."""
    e = direct_illuminance(sources, Sensors.horizontal(points), occluder, offset)
    return e if interreflected is None else e + interreflected(points)


def check_luminaires_for_ti(scene_path: str, sources: list[PlacedSource], indices: list[int]) -> None:
    for src, i in zip(sources, indices):
        if src.position[1] <= OBSERVER_EYE:
            raise FormatError(
                scene_path,
                f"lights[{i}]",
                f"a luminaire at y = {src.position[1]:g} m is not above the observer's eye ({OBSERVER_EYE:g} m): "
                "TI is defined for luminaires above the road",
            )


def evaluate_road(
    sources: list[PlacedSource],
    road: Road,
    table: RTable,
    maintenance: float = 1.0,
    verge: float = 0.0,
    occluder=None,
    offset: float = 1e-4,
    interreflected: Interreflected | None = None,
) -> RoadResult:
    """Every EN 13201-3 figure of the field (see the module docstring); the illuminance with
    `interreflected`'s interreflections when given."""
    lum_grid = road.luminance_grid()
    pts = lum_grid.points()
    nz, nx = lum_grid.shape
    observers = road.observers()
    lum = np.stack([road_luminance(sources, pts, o, table, occluder, offset).reshape(nz, nx) for o in observers])
    l_av_each = lum.mean(axis=(1, 2))
    u0_each = lum.min(axis=(1, 2)) / np.maximum(l_av_each, 1e-30)
    # U_l: along the centre line of the observer's own lane (the middle of its three columns)
    ul_each = []
    for lane in range(road.lanes):
        line = lum[lane][:, 3 * lane + 1]
        ul_each.append(line.min() / line.max() if line.max() > 0 else 0.0)
    l_av_new = float(l_av_each.min())
    ti = 0.0
    steps = en13201_points_along(road.spacing)
    first = min(sources, key=lambda s: abs(s.position[2] - road.z0)) if sources else None
    for eye in observers:
        if first is None:
            break
        start = road.z0 - (first.position[1] - OBSERVER_EYE) / math.tan(math.radians(SCREENING_DEG))
        for k in range(steps):
            at = np.array([eye[0], OBSERVER_EYE, start + k * road.spacing / steps])
            ti = max(ti, threshold_increment(veiling_luminance(sources, at, occluder, offset), l_av_new))
    e_grid = road.illuminance_grid()
    e = horizontal_illuminance(sources, e_grid.points(), occluder, offset, interreflected).reshape(e_grid.shape)
    eir = edge_illuminance_ratio(sources, road, verge, occluder, offset, interreflected) if verge > 0 else None
    e = e * maintenance
    return RoadResult(
        luminance=lum * maintenance,
        l_av=float(l_av_each.min()) * maintenance,
        u0=float(u0_each.min()),
        ul=float(min(ul_each)),
        ti=float(ti),
        eir=eir,
        e_av=float(e.mean()),
        e_min=float(e.min()),
        u0_e=float(e.min() / e.mean()) if e.mean() > 0 else 0.0,
        illuminance=e,
    )


def edge_illuminance_ratio(
    sources, road: Road, verge: float, occluder=None, offset: float = 1e-4, interreflected: Interreflected | None = None
) -> float:
    """R_EI: outside strip over inside strip, the worse of the two edges."""
    strip = min(EIR_MAX_STRIP, road.width / 2, verge)
    z = road.along()
    ratios = []
    for edge, outward in ((road.x0, -1.0), (road.x0 + road.width, 1.0)):
        means = []
        for lo, hi in ((edge, edge + outward * strip), (edge - outward * strip, edge)):
            x = centres(min(lo, hi), max(lo, hi), 3)
            zz, xx = np.meshgrid(z, x, indexing="ij")
            pts = np.stack([xx.ravel(), np.zeros(xx.size), zz.ravel()], axis=1)
            means.append(horizontal_illuminance(sources, pts, occluder, offset, interreflected).mean())
        outside, inside = means
        ratios.append(outside / inside if inside > 0 else 0.0)
    return float(min(ratios))
