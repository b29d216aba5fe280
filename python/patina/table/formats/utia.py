"""UTIA BRDF database binaries (.bin; J. Filip and R. Vavra, "Template-Based Sampling of
Anisotropic BRDFs", Computer Graphics Forum 33(7), 2014; http://btf.utia.cas.cz/).

The file is 3 x (6 x 48) x (6 x 48) float64 values, little endian, and nothing else:
for each of R, G, B, for each incident direction (theta_i = 0, 15, ..., 75 degrees, phi_i
= 0, 7.5, ..., 352.5 degrees, theta slowest), for each outgoing direction likewise. So
the format has no signature: it is recognised by the .bin extension, and a .bin file of
any other size is refused naming the size expected. The values are kept as stored (the
database's relative units; djb's reader rescales them).
"""

from __future__ import annotations

import math
from typing import NoReturn

import numpy as np

from patina.errors import FormatError
from patina.table.formats.measurement_noise import checked_measurement
from patina.table.formats.tabledata import TableData
from patina.table.formats.whole_file import read_whole_file

THETAS, PHIS, PLANES = 6, 48, 3
THETA_STEP_DEG, PHI_STEP_DEG = 15.0, 7.5
SHAPE = (PLANES, THETAS, PHIS, THETAS, PHIS)
FILE_BYTES = math.prod(SHAPE) * 8  # 1 990 656


def utia_axes() -> list[np.ndarray]:
    """(theta_i, phi_i, theta_o, phi_o) in radians; phi has a knot at 360 deg repeating 0 so
    that interpolation wraps."""
    theta = np.radians(np.arange(THETAS) * THETA_STEP_DEG)
    phi = np.radians(np.arange(PHIS + 1) * PHI_STEP_DEG)
    return [theta, phi, theta, phi]


def read_utia(path: str) -> TableData:
    raw = read_whole_file(path, FILE_BYTES, exact=FILE_BYTES, what="a UTIA .bin BRDF (3 x 288 x 288 float64)")
    values = np.frombuffer(raw, dtype="<f8").reshape(SHAPE)

    def refuse(flat: int, problem: str) -> NoReturn:
        channel, ti, pi, to, po = np.unravel_index(flat, SHAPE)
        raise FormatError(
            path,
            f"byte {flat * 8}",
            f"value {values.ravel()[flat]:g} ({'RGB'[channel]}, theta_i {ti * THETA_STEP_DEG:g}, "
            f"phi_i {pi * PHI_STEP_DEG:g}, theta_o {to * THETA_STEP_DEG:g}, phi_o {po * PHI_STEP_DEG:g} deg): "
            + problem,
        )

    values, noise = checked_measurement(values, refuse)
    if values.max() > np.finfo(np.float32).max:
        raise FormatError(path, "file", "values beyond float32")
    grid = np.moveaxis(values, 0, -1)  # (ti, pi, to, po, 3)
    grid = np.concatenate([grid, grid[:, :1]], axis=1)  # phi_i = 360 deg
    grid = np.concatenate([grid, grid[:, :, :, :1]], axis=3)  # phi_o = 360 deg
    return TableData(
        parametrization="anisotropic",
        axes=utia_axes(),
        values=np.ascontiguousarray(grid, dtype=np.float32),
        channel_kind="rgb",
        units="1/sr",
        provenance=(
            "UTIA BRDF database binary (6 theta x 48 phi per direction, theta 0-75 deg, RGB float64; "
            "values as stored, the database's relative units)" + (f"; {noise}" if noise else "")
        ),
    )
