"""RGL .bsdf materials as Patina tables: the file is evaluated by its own rule (natively,
brdf/rgl/ through rgl_native.py) at the knots of a Patina grid dense where the lobe is, and
the error of that resampling, measured against the double-precision reference evaluation
(rgl_brdf.py) at direction pairs off the grid, goes into the provenance.

Isotropic files become halfdiff tables (theta_h, theta_d, phi_d) with theta_h knots on
the format's own square-root mapping (theta_h = pi/2 u^2: a quarter of the knots within
7 degrees of the normal) and phi_d over [-pi, pi]: no symmetry is assumed (folding phi_d by
reciprocity, as MERL tables do, put the file's own non-reciprocity into the error: 95% 12%
instead of 3% on a plastic); anisotropic ones become (theta_i, phi_i, theta_o, phi_o) tables.
"""

from __future__ import annotations

import math
import sys

import numpy as np

from patina.progress import Progress
from patina.table.angles import angles_to_directions, halfdiff_to_directions
from patina.table.formats.resample import relative_error
from patina.table.formats.rgl_brdf import RglBrdf, read_rgl_brdf, u_to_theta
from patina.table.formats.rgl_native import native_rgl
from patina.table.formats.tabledata import TableData, table_from_data

HALFDIFF_KNOTS = (90, 46, 73)  # theta_h, theta_d, phi_d (over [-pi, pi], 5 deg)
ANISOTROPIC_KNOTS = (12, 17, 46, 73)  # theta_i, phi_i, theta_o, phi_o
ERROR_PAIRS = 8192  # direction pairs off the grid at which the resampling error is measured
CHUNK = 16384  # pairs evaluated at a time (progress, and memory in proportion)
MIN_COS = 1e-3  # the grid's directions are evaluated at least this far above the horizon (_above_horizon)


def _evaluate(brdf: RglBrdf, wi: np.ndarray, wo: np.ndarray, what: str) -> np.ndarray:
    """The grid's values by the native evaluator (brdf/rgl/, ~80x the reference's speed); the
    reference evaluates the pairs the resampling error is measured at."""
    native = native_rgl(brdf)
    wi, wo = wi.astype(np.float32), wo.astype(np.float32)
    out = np.empty((len(wi), brdf.channels))
    # ~1 s for the default grids: the bar shows only on a terminal, where it cannot clutter a log
    with Progress(len(wi), what, unit="pair", enabled=sys.stderr.isatty()) as progress:
        for start in range(0, len(wi), CHUNK):
            stop = min(start + CHUNK, len(wi))
            out[start:stop] = native.eval(wi[start:stop], wo[start:stop], width=0, threads=1)
            progress.update(stop)
    return out


def _above_horizon(d: np.ndarray) -> np.ndarray:
    """Directions lifted to at least MIN_COS above the horizon. The file holds f cos(theta_o), and
    f is that over cos(theta_o): at the grid's horizon knots (theta_d = 90 deg) cos(theta_o) is
    ~6e-17 and f ~1e17, which the renderer refuses (beyond its 32-bit floats); 0.06 deg above
    the horizon the glossy test plastic's largest value is ~2e4."""
    lifted = d.copy()
    lifted[:, 2] = np.maximum(lifted[:, 2], MIN_COS)
    return lifted / np.linalg.norm(lifted, axis=1, keepdims=True)


def _grid(brdf: RglBrdf) -> tuple[str, list[np.ndarray], np.ndarray, np.ndarray]:
    if brdf.isotropic:
        nh, nd, npd = HALFDIFF_KNOTS
        axes = [u_to_theta(np.linspace(0, 1, nh)), np.linspace(0, math.pi / 2, nd), np.linspace(-math.pi, math.pi, npd)]
        th, td, pd = np.meshgrid(*axes, indexing="ij")
        wi, wo = halfdiff_to_directions(th, td, pd)
        return "halfdiff", axes, _above_horizon(wi), _above_horizon(wo)
    nti, npi, nto, npo = ANISOTROPIC_KNOTS
    axes = [
        np.linspace(0, math.radians(85), nti),
        np.linspace(0, 2 * math.pi, npi),
        np.linspace(0, math.radians(89), nto),
        np.linspace(0, 2 * math.pi, npo),
    ]
    ti, pi, to, po = np.meshgrid(*axes, indexing="ij")
    return (
        "anisotropic",
        axes,
        angles_to_directions(ti.ravel(), pi.ravel()),
        angles_to_directions(to.ravel(), po.ravel()),
    )


def error_pairs(count: int, seed: int = 29) -> tuple[np.ndarray, np.ndarray]:
    """Half uniform over both hemispheres, half within ~15 degrees of the mirror direction."""
    rng = np.random.default_rng(seed)
    ci = np.sqrt(rng.uniform(0.02, 1.0, count))  # cosine-distributed incidence, not grazing
    wi = angles_to_directions(np.arccos(ci), rng.uniform(0, 2 * math.pi, count))
    wo = angles_to_directions(np.arccos(rng.uniform(0.02, 1.0, count)), rng.uniform(0, 2 * math.pi, count))
    half = count // 2
    mirror = wi[:half] * np.array([-1.0, -1.0, 1.0]) + rng.normal(scale=0.25, size=(half, 3))
    mirror[:, 2] = np.abs(mirror[:, 2]) + 0.05
    wo[:half] = mirror / np.linalg.norm(mirror, axis=1, keepdims=True)
    return wi, wo


def read_rgl(path: str) -> TableData:
    """The .bsdf file as a TableData (linear sRGB; spectral files converted, CIE 1931 2 deg,
    D65), its resampling error in the provenance."""
    brdf = read_rgl_brdf(path)
    parametrization, axes, wi, wo = _grid(brdf)
    values = _evaluate(brdf, wi, wo, "resampling the RGL file")
    shape = tuple(a.size for a in axes)
    kind = "isotropic" if brdf.isotropic else f"anisotropic, phi_i over 360/{brdf.reduction} deg"
    converted = ", converted to linear sRGB (CIE 1931 2 deg, D65)" if brdf.channel_kind == "spectral" else ""
    data = TableData(
        parametrization=parametrization,
        axes=axes,
        values=values.reshape(*shape, brdf.channels).astype(np.float32),
        channel_kind="rgb",
        provenance=(
            f"RGL tensor_file 1.0 ({kind}, {brdf.source_channels}{converted}, "
            f"jacobian {'on' if brdf.jacobian else 'off'})"
            + (f" '{brdf.description[:120]}'" if brdf.description else "")
            + f"; evaluated by the format's rule onto a {parametrization} {' x '.join(map(str, shape))} grid"
        ),
    )
    table = table_from_data(data)
    wi, wo = error_pairs(ERROR_PAIRS)
    on_table = table.eval(wi.astype(np.float32), wo.astype(np.float32), width=1, threads=0)
    err = relative_error(np.asarray(on_table, dtype=np.float64), brdf.eval(wi, wo))
    data.provenance += (
        f"; resampling error against the file's own evaluation at {ERROR_PAIRS} direction pairs off the grid: "
        f"median {err['median']:.3g}, 95% {err['p95']:.3g}, max {err['max']:.3g}"
    )
    return data
