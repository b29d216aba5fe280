"""The bundled car-paint base table: its irregular half/difference grid and its measured accuracy.

The table holds `carpaint.coated_base` (the Günther et al. base BRDF at the directions
refracted through the clear coat) on a (theta_h, theta_d, phi_d) grid of the *outside*
directions. Half/difference angles put every paint lobe at theta_h = 0, whatever the
incidence, so one axis dense near 0 resolves all of them; phi_d is folded into [0, 90 deg]
(the model is isotropic and reciprocal). tools/make_carpaint.py writes it; the test and the
provenance file use `interpolation_errors` to say how far the table is from the model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.synthetic.analytic import BrdfFunction, halfdiff_to_directions
from patina.synthetic.carpaint import CLEAR_COAT_ETA, PaintParameters, coated_base
from patina.table.brdf import Brdf
from patina.table.formats.tabledata import TableData

BUNDLED_PAINT = "blue"
PROVENANCE = (
    "Patina tools/make_carpaint.py: base BRDF of Günther et al. 2005 (VMV), paint '{name}', "
    "evaluated at the directions refracted through a smooth clear coat of index {eta}; "
    "halfdiff grid of the outside directions; goes under a Fresnel coat attenuating by (1-F_i)(1-F_o)"
)


def theta_h_axis() -> np.ndarray:
    """0.2 deg steps to 4 deg (the narrowest lobe is about 1.7 deg wide outside), then steps growing 10% a knot."""
    knots = list(np.arange(0.0, 4.0, 0.2))
    step = 0.2
    knots.append(4.0)
    while knots[-1] + step < 90.0:
        knots.append(knots[-1] + step)
        step = min(step * 1.1, 4.0)
    return np.radians(np.array([*knots, 90.0]))


def theta_d_axis() -> np.ndarray:
    """0..90 deg, denser towards grazing where Fresnel and refraction change fastest."""
    u = np.linspace(0.0, 1.0, 37)
    return np.radians(90.0 * np.sin(u * np.pi / 2))


def phi_d_axis() -> np.ndarray:
    """0..90 deg uniform (phi mirror folds the rest)."""
    return np.radians(np.linspace(0.0, 90.0, 29))


def table_axes() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return theta_h_axis(), theta_d_axis(), phi_d_axis()


def base_table(paint: PaintParameters, eta: float = CLEAR_COAT_ETA) -> TableData:
    """The paint's coated base sampled on `table_axes()`, RGB, float32, reciprocity + phi mirror."""
    axes = table_axes()
    th, td, pd = np.meshgrid(*axes, indexing="ij")
    wi, wo = halfdiff_to_directions(th, td, pd)
    values = coated_base(paint, eta)(wi, wo).reshape(*th.shape, 3)
    return TableData(
        "halfdiff",
        [a.astype(np.float64) for a in axes],
        values.astype(np.float32),
        "rgb",
        provenance=PROVENANCE.format(name=paint.name, eta=eta),
        symmetry={"reciprocity", "phi_mirror"},
    )


def random_pairs(n: int, rng: np.random.Generator, max_theta_deg: float = 85.0) -> tuple[np.ndarray, np.ndarray]:
    """n direction pairs, each direction uniform in solid angle over the cap theta < max_theta."""
    zmin = math.cos(math.radians(max_theta_deg))

    def cap() -> np.ndarray:
        z = rng.uniform(zmin, 1.0, n)
        phi = rng.uniform(0.0, 2 * math.pi, n)
        s = np.sqrt(1.0 - z * z)
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=1)

    return cap(), cap()


def peak_pairs(
    n: int, rng: np.random.Generator, max_theta_h_deg: float = 3.0, max_theta_deg: float = 85.0
) -> tuple[np.ndarray, np.ndarray]:
    """n pairs near the specular peak: outside half vector within max_theta_h of the normal."""
    out_i, out_o = [], []
    count = 0
    while count < n:
        th = np.radians(max_theta_h_deg) * np.sqrt(rng.uniform(0.0, 1.0, 2 * n))  # uniform over the small disc
        td = np.arccos(rng.uniform(0.0, 1.0, 2 * n))
        pd = rng.uniform(0.0, 2 * math.pi, 2 * n)
        wi, wo = halfdiff_to_directions(th, td, pd)
        # spin the pair about the normal so phi_h is random too
        a = rng.uniform(0.0, 2 * math.pi, 2 * n)
        c, s = np.cos(a), np.sin(a)
        wi = np.stack([c * wi[:, 0] - s * wi[:, 1], s * wi[:, 0] + c * wi[:, 1], wi[:, 2]], axis=1)
        wo = np.stack([c * wo[:, 0] - s * wo[:, 1], s * wo[:, 0] + c * wo[:, 1], wo[:, 2]], axis=1)
        zmin = math.cos(math.radians(max_theta_deg))
        keep = (wi[:, 2] > zmin) & (wo[:, 2] > zmin)
        out_i.append(wi[keep])
        out_o.append(wo[keep])
        count += int(keep.sum())
    return np.concatenate(out_i)[:n], np.concatenate(out_o)[:n]


@dataclass(frozen=True)
class ErrorStats:
    """Relative error |table - model| / model over all pairs and channels."""

    pairs: int
    median: float
    p99: float
    max: float

    def as_text(self) -> str:
        return f"median {100 * self.median:.2f}%, 99th percentile {100 * self.p99:.2f}%, max {100 * self.max:.2f}%"


def interpolation_errors(brdf: Brdf, model: BrdfFunction, wi: np.ndarray, wo: np.ndarray) -> ErrorStats:
    """How far the table's SIMD evaluation is from the analytic model at these pairs."""
    table = brdf.eval(wi.astype(np.float32), wo.astype(np.float32)).astype(np.float64)
    # the model at the float32 directions the table saw, so only interpolation is measured
    exact = model(wi.astype(np.float32).astype(np.float64), wo.astype(np.float32).astype(np.float64))
    rel = np.abs(table - exact) / exact
    return ErrorStats(len(wi), float(np.median(rel)), float(np.percentile(rel, 99)), float(rel.max()))
