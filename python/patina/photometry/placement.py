"""A luminaire placed in a scene (docs/luminaires.md, docs/scene.md): its axes in the world and
the radiometric RGB of one of its candela, TILT included. The renderer (render/prepare.py) and
the Mitsuba conversion (scene/mitsuba.py) both place luminaires through these."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from patina.colour_constants import photometric_to_rgb
from patina.photometry.luminaire import Luminaire


def luminaire_axes(aim: Any, rotation_deg: float, kind: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The luminaire's x, y, z axes in the world. Type C: the nadir (-z) along `aim`; type B:
    the beam axis (+z) along `aim`. x is the world's +x (or +z, when aim is along x) made
    perpendicular to the axis, then turned by `rotation` degrees about it; y = z x x."""
    a = np.asarray(aim, np.float64) / np.linalg.norm(aim)
    z = -a if kind == "C" else a
    ref = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    x = ref - (ref @ z) * z
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    t = math.radians(rotation_deg)
    x, y = math.cos(t) * x + math.sin(t) * y, -math.sin(t) * x + math.cos(t) * y
    return x, y, z


def tilt_factor(lum: Luminaire, aim: Any) -> float:
    """An IES TILT table's factor: the lamp's output against its tilt from the nadir-down
    position the file was measured in, here the angle between `aim` and straight down."""
    tilt = lum.photometry.tilt
    if tilt is None or not len(tilt.angles_deg):
        return 1.0
    a = np.asarray(aim, np.float64) / np.linalg.norm(aim)
    angle = math.degrees(math.acos(max(-1.0, min(1.0, -a[1]))))
    return float(np.interp(angle, tilt.angles_deg, tilt.factors))


def rgb_per_candela(lum: Luminaire, aim: Any, multiplier: float, color: Any) -> tuple[float, float, float]:
    """W/sr of Patina's radiometric RGB (683 lm/W of luminance) per candela of the table, of
    the light's colour, times its multiplier and the TILT factor."""
    return photometric_to_rgb(multiplier * tilt_factor(lum, aim), color)
