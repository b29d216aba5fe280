"""A small library for the batch tests: three tables sampled from analytic plastics (small grids,
so a fit and a preview take a fraction of a second), a corrupt .ptab and a file that is no table."""

from __future__ import annotations

import os

import numpy as np

import patina
from patina.batch import Settings
from patina.synthetic.analytic import plastic, sample_isotropic
from patina.table.formats import table_from_data

THETA = np.radians(np.linspace(0, 85, 10))
PHI = np.radians(np.linspace(0, 180, 13))
PLASTICS = {
    "red.ptab": ((0.5, 0.08, 0.06), 0.2),
    "green.ptab": ((0.08, 0.4, 0.1), 0.3),
    "blue.ptab": ((0.1, 0.15, 0.5), 0.4),
}
GOOD = sorted(PLASTICS)
BAD = "corrupt.ptab"
# tiny previews, one model, one start: the whole batch in seconds even on a loaded 2-core machine
QUICK = Settings(steps=("validate", "fit", "preview"), models=("ggx+lambert",), starts=1, width=24, height=18, spp=1)


def write_plastic(
    path: str, diffuse: tuple[float, ...], roughness: float, theta_knots: int = 0, phi_knots: int = 0
) -> None:
    theta = np.radians(np.linspace(0, 85, theta_knots)) if theta_knots else THETA
    phi = np.radians(np.linspace(0, 180, phi_knots)) if phi_knots else PHI
    data = sample_isotropic(plastic(diffuse=diffuse, roughness=roughness), theta, theta, phi, "batch test")
    patina.Brdf(table_from_data(data), "synthetic").save(path)


def make_library(folder: str) -> str:
    os.makedirs(folder, exist_ok=True)
    for name, (diffuse, roughness) in PLASTICS.items():
        write_plastic(os.path.join(folder, name), diffuse, roughness)
    with open(os.path.join(folder, BAD), "wb") as f:
        f.write(b"PTAB\r\n\x1a\n" + bytes(40))  # the magic, then nothing a reader accepts
    with open(os.path.join(folder, "README.md"), "w") as f:
        f.write("Measured in March to ASTM E1392.\n")  # a note: not read as an ASTM table for the word
    return folder
