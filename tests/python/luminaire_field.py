"""The analytic illuminance a placed luminaire gives a floor: what the luminaire tests (the
renderer's, the Mitsuba conversion's) compare against."""

from __future__ import annotations

from typing import Any

import numpy as np

from patina.photometry.luminaire import load_luminaire
from patina.photometry.placement import luminaire_axes


def floor_illuminance(path: str, position: Any, aim: Any, rotation: float, points: np.ndarray) -> np.ndarray:
    """E = I cos / d^2 at `points` (..., 3) on the floor y = 0 (normal +y), I the candela the
    file gives towards each point from the luminaire at `position` aimed along `aim` and turned
    by `rotation` degrees: lux, before any multiplier, colour or TILT."""
    lum = load_luminaire(path)
    x, y, z = luminaire_axes(aim, rotation, lum.kind)
    out = points - np.asarray(position, np.float64)  # from the luminaire to the floor
    d2 = (out**2).sum(-1)
    w = out / np.sqrt(d2)[..., None]
    candela = lum.intensity_at(np.stack([w @ x, w @ y, w @ z], -1).reshape(-1, 3)).reshape(d2.shape)
    return candela * (-w[..., 1]) / d2
