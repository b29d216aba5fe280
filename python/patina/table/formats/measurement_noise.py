"""Values a measurement leaves slightly below zero: noise about zero, not a broken file.

A measured BRDF near zero (grazing angles, far from a lobe) is a small signal minus a
detector's dark offset, so real files hold values a little below zero: NVIDIA's own
measured car paints in the MDL SDK (examples/mdl/nvidia/sdk_examples/resources/
carpaint_*.mbsdf) have 11-14 % of their values negative, down to -0.3 % of their largest.
Refusing those files would refuse the format's reference data; keeping them would put
negative reflectance into fits and renders. So values down to NOISE_FRACTION of the
table's largest are set to 0 and counted in the table's provenance; a value further below
zero is no noise and the file is refused, naming where it is.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NoReturn

import numpy as np

NOISE_FRACTION = 0.01


def noise_floor(values: np.ndarray) -> float:
    """The lowest value taken as noise about zero (0 for a table with nothing above zero)."""
    largest = float(values.max()) if values.size else 0.0
    return -NOISE_FRACTION * largest if largest > 0 else 0.0


def checked_measurement(values: np.ndarray, refuse: Callable[[int, str], NoReturn]) -> tuple[np.ndarray, str]:
    """(values with the noise below zero set to 0, a provenance note or ""). refuse(flat index,
    problem) is called for the first value not finite or below the noise floor, and raises."""
    finite = np.isfinite(values)
    if not finite.all():
        refuse(int(np.argmax(~finite.ravel())), "not finite")
    floor = noise_floor(values)
    broken = values < floor
    if broken.any():
        refuse(int(np.argmax(broken.ravel())), f"negative beyond measurement noise (below {floor:g})")
    count = int((values < 0).sum())
    if count == 0:
        return values, ""
    lowest, largest = float(values.min()), float(values.max())
    note = (
        f"{count} values slightly below 0 set to 0 (measurement noise: down to {lowest:.3g}, "
        f"{100 * -lowest / largest:.2g} % of the largest value)"
    )
    return np.maximum(values, 0), note
