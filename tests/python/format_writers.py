"""Writers of the imported formats for the tests (no test downloads a file): each writes a
known analytic BRDF `model` (patina.synthetic.analytic) the way the format's specification
lays it out, so a reader's result can be checked against the model."""

from __future__ import annotations

import struct

import numpy as np

from patina.synthetic.analytic import anisotropic_grid, isotropic_grid
from patina.table.angles import angles_to_directions
from patina.table.formats.mdl import MAGIC, mdl_axes
from patina.table.formats.utia import PHIS, THETAS
from patina.table.formats.zemax import scatter_directions

# a plane-symmetrical Zemax file's angle lists, degrees
ZEMAX_AOI = [0, 15, 30, 45, 60, 75]
ZEMAX_AZIMUTH = list(range(0, 181, 15))
ZEMAX_RADIAL = list(range(0, 91, 5))


def zemax_text(
    model,
    channels=("Monochrome",),
    scatter_type="BRDF",
    data=True,
    aoi=ZEMAX_AOI,
    azimuth=ZEMAX_AZIMUTH,
    radial=ZEMAX_RADIAL,
) -> str:
    lines = ["# written by Patina's tests", "Source  Measured", "Symmetry  PlaneSymmetrical"]
    lines += [f"SpectralContent  {'XYZ' if len(channels) == 3 else 'Monochrome'}", f"ScatterType  {scatter_type}"]
    lists = {"SampleRotation": [0], "AngleOfIncidence": aoi, "ScatterAzimuth": azimuth, "ScatterRadial": radial}
    for key, values in lists.items():
        lines += [f"{key}  {len(values)}", "  ".join(str(v) for v in values)]
    lines.append("")
    for c, label in enumerate(channels):
        if not data:
            break
        lines += [label, "DataBegin"]
        for theta in aoi:
            ti = np.radians(theta)
            a, d = np.meshgrid(np.radians(azimuth), np.radians(radial), indexing="ij")
            wo = scatter_directions(np.full(a.shape, ti), np.zeros(a.shape), a, d).reshape(-1, 3)
            wi = np.repeat(angles_to_directions(ti, 0.0)[None], len(wo), axis=0)
            f = np.where(wo[:, 2] > 0, model(wi, wo)[:, c % 3], 0.0).reshape(a.shape)
            lines.append("TIS 0.5")
            lines += ["  ".join(f"{v:.6e}" for v in row) for row in f]
        lines.append("DataEnd")
    return "\n".join(lines) + "\n"


def mbsdf_bytes(
    model,
    res_theta: int = 9,
    res_phi: int = 12,
    rgb: bool = True,
    parts=("REFLECTION",),
    metadata: str = 'author="tests"',
) -> bytes:
    """An .mbsdf of `model`: metadata, then one block per part (the transmission block holds 0.1)."""
    out = MAGIC + metadata.encode() + b"\n"
    th, to, pd = mdl_axes(res_theta, res_phi)
    wi, wo = isotropic_grid(th, to, pd)
    values = model(wi, wo)
    if not rgb:
        values = values[:, 1:2]
    for part in parts:
        block = values if part != "TRANSMISSION" else np.full_like(values, 0.1)
        out += f"MBSDF_DATA_{part}=\n".encode() + struct.pack("<III", 1 if rgb else 0, res_theta, res_phi)
        out += block.astype("<f4").tobytes()
    return out


def utia_values(model) -> np.ndarray:
    """(3, 6, 48, 6, 48) float64: `model` at the database's directions, R, G, B planes."""
    theta = np.radians(np.arange(THETAS) * 15.0)
    phi = np.radians(np.arange(PHIS) * 7.5)
    wi, wo = anisotropic_grid(theta, phi, theta, phi)
    return np.moveaxis(model(wi, wo).reshape(THETAS, PHIS, THETAS, PHIS, 3), -1, 0)
