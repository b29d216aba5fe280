"""Small measured tables the RGL export tests share, and a small RGL file the render tests
render: quick to build, resampled in seconds."""

from __future__ import annotations

import math

import numpy as np

from patina.synthetic.analytic import plastic, sample_isotropic
from patina.table.angles import halfdiff_to_directions
from patina.table.brdf import Brdf
from patina.table.formats.rgl_writer import RglLayout, write_rgl
from patina.table.formats.tabledata import TableData, table_from_data

MODEL = plastic(diffuse=(0.5, 0.2, 0.1), specular=0.04, roughness=0.25)
WAVELENGTHS = np.linspace(400.0, 700.0, 7)
# a reflectance shape over WAVELENGTHS (reddish), times the model's green channel
SPECTRAL_SHAPE = np.array([0.2, 0.25, 0.3, 0.45, 0.7, 0.85, 0.9])


def _halfdiff(values_of) -> tuple[list[np.ndarray], np.ndarray]:
    axes = [
        np.radians(np.linspace(0, 1, 48) ** 2 * 90),
        np.radians(np.linspace(0, 90, 46)),
        np.radians(np.linspace(0, 180, 37)),
    ]
    th, td, pd = np.meshgrid(*axes, indexing="ij")
    wi, wo = halfdiff_to_directions(th, td, pd)
    return axes, values_of(wi, wo).reshape(*(a.size for a in axes), -1)


def plastic_table() -> Brdf:
    """The plastic on a 48 x 46 x 37 halfdiff grid (MERL's layout, coarser)."""
    axes, values = _halfdiff(MODEL)
    data = TableData(
        "halfdiff", axes, values.astype(np.float32), "rgb", symmetry={"reciprocity"}, provenance="test plastic"
    )
    return Brdf(table_from_data(data), "plastic.ptab", "ptab")


def spectral_table() -> Brdf:
    axes, values = _halfdiff(lambda wi, wo: MODEL(wi, wo)[:, 1:2] * SPECTRAL_SHAPE[None, :])
    data = TableData(
        "halfdiff", axes, values.astype(np.float32), "spectral", wavelengths=WAVELENGTHS, symmetry={"reciprocity"}
    )
    return Brdf(table_from_data(data), "spectral.ptab", "ptab")


def shallow_table() -> Brdf:
    """Measured at incidences up to 60 degrees only: a hole over the range an RGL file holds."""
    t = np.radians(np.linspace(0, 60, 7))
    data = sample_isotropic(MODEL, t, np.radians(np.linspace(0, 89, 30)), np.linspace(0, math.pi, 19), "shallow")
    return Brdf(table_from_data(data), "shallow.ptab", "ptab")


# A glossy plastic (GGX alpha 0.15 under a dark base) in a small RGL layout: what the render
# tests write and render (its lobe is narrow enough that cosine sampling is noisy).
GLOSSY = plastic(diffuse=(0.06, 0.05, 0.04), specular=0.6, roughness=0.15)
SMALL_LAYOUT = RglLayout(theta_i=8, ndf=(12, 32), sigma=(12, 24), vndf=(24, 32), values=(24, 24))


def write_glossy_rgl(path: str, spectral: bool = False) -> str:
    """The glossy plastic as RGB, or (`spectral`) its green channel times SPECTRAL_SHAPE at WAVELENGTHS."""
    if spectral:
        reddish = lambda wi, wo: GLOSSY(wi, wo)[:, 1:2] * SPECTRAL_SHAPE[None, :]  # noqa: E731
        write_rgl(path, reddish, wavelengths=WAVELENGTHS, layout=SMALL_LAYOUT, description="spectral test plastic")
    else:
        write_rgl(path, GLOSSY, layout=SMALL_LAYOUT, description="glossy test plastic")
    return path
