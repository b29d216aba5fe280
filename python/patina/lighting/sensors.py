"""What a sensor measures, given the light arriving from one direction.

Planar sensors (horizontal, vertical at an azimuth, perpendicular to a surface) take
E_n cos(incidence) on the lit side. Cylindrical and semi-cylindrical sensors are EN 13201-3's
vertical cylinders (its clause 7.4): a small cylinder's mean illuminance over its curved
surface, E_n sin(eps) / pi for the full cylinder and E_n sin(eps) (1 + cos(alpha)) / pi for
the half facing `facing`, where eps is the incidence angle from the vertical and alpha the
horizontal angle between the light's plane and the half-cylinder's facing. E_n is the
illuminance on a surface normal to the light (I / d^2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError

UP = np.array([0.0, 1.0, 0.0])  # the scenes' vertical (docs/scene.md: y up)
KINDS = ("planar", "cylindrical", "semicylindrical")


@dataclass(frozen=True)
class Sensors:
    """n sensors at `points` (n, 3). planar: unit `normals` (n, 3); semicylindrical: the
    horizontal unit direction each half-cylinder faces, in `normals`; cylindrical: unused."""

    points: np.ndarray
    normals: np.ndarray
    kind: str = "planar"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"sensor kind '{self.kind}': one of {', '.join(KINDS)}")

    @classmethod
    def horizontal(cls, points: np.ndarray, facing_up: bool = True) -> Sensors:
        n = np.tile([0.0, 1.0 if facing_up else -1.0, 0.0], (len(points), 1))
        return cls(np.asarray(points, np.float64), n)

    @classmethod
    def vertical(cls, points: np.ndarray, azimuth_deg: float) -> Sensors:
        """Facing the horizontal direction `azimuth_deg` from +x towards +z."""
        return cls(np.asarray(points, np.float64), np.tile(horizontal_direction(azimuth_deg), (len(points), 1)))

    @classmethod
    def cylindrical(cls, points: np.ndarray) -> Sensors:
        return cls(np.asarray(points, np.float64), np.zeros((len(points), 3)), "cylindrical")

    @classmethod
    def semicylindrical(cls, points: np.ndarray, azimuth_deg: float) -> Sensors:
        n = np.tile(horizontal_direction(azimuth_deg), (len(points), 1))
        return cls(np.asarray(points, np.float64), n, "semicylindrical")

    def part(self, begin: int, end: int) -> Sensors:
        return Sensors(self.points[begin:end], self.normals[begin:end], self.kind)

    def response(self, towards_light: np.ndarray) -> np.ndarray:
        """The factor multiplying E_n for unit directions (n, 3) from each sensor to its light."""
        u = towards_light
        if self.kind == "planar":
            return np.maximum(np.einsum("ij,ij->i", u, self.normals), 0.0)
        horizontal = u - np.outer(u @ UP, UP)
        sin_eps = np.linalg.norm(horizontal, axis=1)
        if self.kind == "cylindrical":
            return sin_eps / np.pi
        # cos(alpha): the light's horizontal direction against the facing (0 when overhead)
        with np.errstate(invalid="ignore", divide="ignore"):
            cos_alpha = np.where(sin_eps > 0, np.einsum("ij,ij->i", horizontal, self.normals) / sin_eps, 0.0)
        return sin_eps * (1.0 + cos_alpha) / np.pi


def horizontal_direction(azimuth_deg: float) -> np.ndarray:
    a = np.radians(azimuth_deg)
    return np.array([np.cos(a), 0.0, np.sin(a)])


SENSOR_SPECS = "up, down, vertical:AZ, cylindrical or semicylindrical:AZ (AZ in degrees from +x towards +z)"


def parse_sensor(spec: str, option: str = "--sensor") -> tuple[str, float | None]:
    """'up', 'down', 'vertical:AZ', 'cylindrical', 'semicylindrical:AZ' -> (name, azimuth)."""
    name, colon, rest = spec.partition(":")
    if name in ("up", "down", "cylindrical") and not colon:
        return name, None
    if name in ("vertical", "semicylindrical") and colon:
        try:
            azimuth = float(rest)
        except ValueError:
            azimuth = float("nan")
        if np.isfinite(azimuth):
            return name, azimuth
    raise FormatError("command line", option, f"expected {SENSOR_SPECS}, got '{spec}'")


def make_sensors(points: np.ndarray, name: str, azimuth: float | None) -> Sensors:
    if name in ("up", "down"):
        return Sensors.horizontal(points, name == "up")
    if name == "vertical":
        return Sensors.vertical(points, azimuth)
    if name == "cylindrical":
        return Sensors.cylindrical(points)
    return Sensors.semicylindrical(points, azimuth)
