"""Exact direct illuminance from delta lights: point, spot and goniometric (IES / EULUMDAT)
luminaires. For such a light the direct illuminance is a finite sum, E = sum over lights of
I(towards the sensor) x response / d^2 with one shadow ray each (DIALux, Relux and AGi32
compute it so), so Patina computes it so too: no sampling, the same numbers on every run.

Intensities are evaluated exactly as the renderer does (the spot's smoothstep cone of
render/delta_intensity_impl.h, the luminaire's candela table through the same bilinear
`_core.Grid2` and the same placement, patina.photometry.placement), in candela:
683 lm/W x Y of the light's radiometric RGB. Shadow rays go through the scene's kd-tree
(`_core.Accel.occluded`), from tmin = the renderer's ray offset to just short of the light.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.colour_constants import LUMINOUS_EFFICACY, luminance
from patina.lighting.sensors import Sensors
from patina.photometry.luminaire import Luminaire, load_luminaire
from patina.photometry.placement import luminaire_axes, tilt_factor
from patina.scene.types import Light, LuminaireLight, PointLight, SpotLight

DELTA_LIGHTS = (PointLight, SpotLight, LuminaireLight)
SHADOW_SHORTEN = 1e-4  # the shadow ray stops this fraction short of the light (as the renderer's)


def is_delta(light: Light) -> bool:
    return isinstance(light, DELTA_LIGHTS)


@dataclass(frozen=True)
class PlacedSource:
    """A delta light as the exact sum needs it: a position and candela towards world directions."""

    position: np.ndarray
    light: Light
    luminaire: Luminaire | None = None
    axes: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    scale: float = 1.0  # candela per unit of the relative intensity or of the table

    @classmethod
    def of(cls, light: Light) -> PlacedSource:
        pos = np.asarray(light.position, np.float64)
        if isinstance(light, LuminaireLight):
            lum = load_luminaire(light.file)
            axes = luminaire_axes(light.aim, light.rotation, lum.kind)
            # the renderer's RGB per candela has luminance multiplier x tilt / 683 (placement.py)
            return cls(pos, light, lum, axes, light.multiplier * tilt_factor(lum, light.aim))
        return cls(pos, light, scale=LUMINOUS_EFFICACY * float(luminance(np.asarray(light.intensity))))

    def candela(self, out: np.ndarray, width: int = 0) -> np.ndarray:
        """Candela towards unit world directions `out` (n, 3) from the light; `width`: the SIMD
        width of the candela table's lookup (0: the CPU's widest)."""
        light = self.light
        if isinstance(light, SpotLight):
            axis = np.asarray(light.direction, np.float64)
            axis = axis / np.linalg.norm(axis)
            cos_inner, cos_outer = math.cos(math.radians(light.inner_angle)), math.cos(math.radians(light.outer_angle))
            t = np.clip((out @ axis - cos_outer) / max(cos_inner - cos_outer, 1e-6), 0.0, 1.0)
            return self.scale * t * t * (3.0 - 2.0 * t)
        if self.luminaire is not None:
            x, y, z = self.axes
            local = out @ np.stack([x, y, z], axis=1)
            return self.scale * self.luminaire.intensity_at(local, width).astype(np.float64)
        return np.full(len(out), self.scale)


@dataclass(frozen=True)
class Arrivals:
    """What reaches n points from k sources: unit directions from each point to each source
    (k, n, 3), squared distances (k, n) and the candela each source sends towards each point,
    0 where a shadow ray is blocked (k, n)."""

    towards: np.ndarray
    d2: np.ndarray
    candela: np.ndarray


def arrivals(
    sources: list[PlacedSource],
    points: np.ndarray,
    occluder=None,
    ray_offset: float = 1e-4,
    width: int = 0,
    threads: int = 0,
) -> Arrivals:
    """Each source's candela towards each point, shadowed by one ray through `occluder` (a
    `_core.Accel`; None: unshadowed), from tmin = `ray_offset` to just short of the source.
    `width`, `threads`: the SIMD width (0: the CPU's widest) of the candela lookups and shadow
    packets, and the shadow rays' threads (0: every core); the result does not depend on them."""
    pts = np.asarray(points, np.float64)
    k, n = len(sources), len(pts)
    towards, d2, cd = np.zeros((k, n, 3)), np.zeros((k, n)), np.zeros((k, n))
    for i, src in enumerate(sources):
        # whole-array arithmetic, no boolean-mask copies: the sum's numpy part is as long as
        # its shadow rays otherwise (10^5 sensors x 20 luminaires, bench/lighting.py)
        to_light = src.position[None, :] - pts
        d2[i] = np.einsum("ij,ij->i", to_light, to_light)
        dist = np.sqrt(d2[i])
        inverse = np.divide(1.0, dist, out=np.zeros(n), where=dist > 0)
        np.multiply(to_light, inverse[:, None], out=towards[i])
        cd[i] = np.where(dist > 0, src.candela(-towards[i], width), 0.0)
        lit = np.flatnonzero(cd[i] > 0)
        if occluder is not None and len(lit):
            blocked = occluder.occluded(
                np.ascontiguousarray(pts[lit], np.float32),
                np.ascontiguousarray(towards[i, lit], np.float32),
                tmax=np.ascontiguousarray(dist[lit] * (1 - SHADOW_SHORTEN), np.float32),
                tmin=float(ray_offset),
                width=width,
                threads=threads,
            )
            cd[i, lit[np.asarray(blocked, bool)]] = 0.0
    return Arrivals(towards, d2, cd)


def direct_illuminance(
    sources: list[PlacedSource],
    sensors: Sensors,
    occluder=None,
    ray_offset: float = 1e-4,
    per_source: bool = False,
    width: int = 0,
    threads: int = 0,
) -> np.ndarray:
    """Lux at each sensor (n,), or (sources, n) with `per_source`: the exact sum over the
    sources of candela x the sensor's response / d^2, each shadowed by one ray (`arrivals`,
    which says what `width` and `threads` are)."""
    a = arrivals(sources, sensors.points, occluder, ray_offset, width, threads)
    out = np.zeros_like(a.d2)
    for i in range(len(sources)):
        lux = a.candela[i] * sensors.response(a.towards[i])
        np.divide(lux, a.d2[i], out=out[i], where=a.candela[i] > 0)
    return out if per_source else out.sum(axis=0)
