"""Exact direct illuminance from delta lights: point, spot and goniometric (IES / EULUMDAT)
luminaires. For such a light the direct illuminance is a finite sum, E = sum over lights of
I(towards the sensor) x response / d^2 with one shadow ray each (DIALux, Relux and AGi32
compute it so), so Patina computes it so too: no sampling, the same numbers on every run.

`direct_illuminance` is the native sum (`_core.direct_illuminance`,
render/lighting/direct_illuminance.h): sensors in SIMD packets, per luminaire the directions,
the candela by the renderer's arithmetic (the spot's smoothstep cone of
render/lights/delta_intensity_impl.h, the candela table through the same bilinear grid and
fast inverse trigonometry), the sensor's response and a packet of shadow rays through the
scene's BVH (built on the first call), from tmin = the renderer's ray offset to just short of
the light. The same bits at every SIMD width and thread count.

`arrivals` is the same sum's parts in double precision with numpy (directions, distances,
candela by `Luminaire.intensity_at`, shadow rays through `_core.Accel.occluded`), for what needs
the directions as well (road luminance from r-tables, glare at an observer's eye) and as the
reference the native sum is tested against. Candela are 683 lm/W x Y of the light's
radiometric RGB, the luminaire placed as the renderer places it (patina.photometry.placement).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.colour_constants import LUMINOUS_EFFICACY, luminance
from patina.lighting.sensors import Sensors
from patina.native import _core
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

    def cone(self) -> tuple[np.ndarray, float, float]:
        """A spot's unit beam axis and the cosines of its inner and outer half-angles."""
        light = self.light
        axis = np.asarray(light.direction, np.float64)
        inner, outer = math.radians(light.inner_angle), math.radians(light.outer_angle)
        return axis / np.linalg.norm(axis), math.cos(inner), math.cos(outer)

    def candela(self, out: np.ndarray, width: int = 0) -> np.ndarray:
        """Candela towards unit world directions `out` (n, 3) from the light; `width`: the SIMD
        width of the candela table's lookup (0: the CPU's widest)."""
        if isinstance(self.light, SpotLight):
            axis, cos_inner, cos_outer = self.cone()
            t = np.clip((out @ axis - cos_outer) / max(cos_inner - cos_outer, 1e-6), 0.0, 1.0)
            return self.scale * t * t * (3.0 - 2.0 * t)
        if self.luminaire is not None:
            x, y, z = self.axes
            local = out @ np.stack([x, y, z], axis=1)
            return self.scale * self.luminaire.intensity_at(local, width).astype(np.float64)
        return np.full(len(out), self.scale)

    def add_to(self, native: _core.DirectSources) -> None:
        """Adds this light to the native sum's luminaires (render/lighting/direct_source.h)."""
        position = _floats(self.position)
        if isinstance(self.light, SpotLight):
            axis, cos_inner, cos_outer = self.cone()
            native.add_spot(position, self.scale, _floats(axis), cos_inner, cos_outer)
        elif self.luminaire is not None:
            x, y, z = (_floats(a) for a in self.axes)
            native.add_goniometric(position, self.scale, x, y, z, self.luminaire.kind == "B", self.luminaire.table)
        else:
            native.add_point(position, self.scale)


def _floats(v: np.ndarray) -> tuple[float, float, float]:
    return float(v[0]), float(v[1]), float(v[2])


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
        # whole-array arithmetic, no boolean-mask copies (they cost as much as the shadow rays)
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
    sources of candela x the sensor's response / d^2, each shadowed by one ray through
    `occluder` (a `_core.Accel`; None: unshadowed) from tmin = `ray_offset`, by the native
    kernel at SIMD `width` (0: the CPU's widest) on `threads` (0: every core); the result does
    not depend on them."""
    native = _core.DirectSources()
    for src in sources:
        src.add_to(native)
    normals = None if sensors.kind == "cylindrical" else np.ascontiguousarray(sensors.normals, np.float32)
    lux = _core.direct_illuminance(
        native,
        np.ascontiguousarray(sensors.points, np.float32),
        normals,
        sensors.kind,
        occluder,
        ray_offset,
        per_source,
        width,
        threads,
    )
    return np.asarray(lux, np.float64)
