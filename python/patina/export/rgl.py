"""Any BRDF Patina evaluates (a measured table of any format, a fit evaluated densely) as an
RGL tensor file (.bsdf), the input of Mitsuba 3's and pbrt-v4's `measured` materials.

The BRDF is resampled into the format's own parameterisation by rgl_writer (Dupuy & Jakob
2018: an NDF from the BRDF's backscatter, the projected areas it implies, one VNDF warp per
incident direction, the values at the warped nodes, their luminance as the second warp).
The values are f cos(theta_o), what the format's readers return (brdf-loader's `eval`:
"f_r * cos"; Mitsuba 3's `measured`, whose `eval` includes the cosine like every Mitsuba
BSDF), so that Mitsuba renders the file as the table.

Channels: `spectra` (a spectral table's own wavelengths, or spectra upsampled from RGB by
Mitsuba's method: rgb_upsampling), as the RGL database's files and pbrt-v4 have them, or
`rgb` (linear sRGB), which Mitsuba's RGB variants need. Before anything is written the file
is read back by Patina's RGL evaluator (rgl_brdf) from its bytes and compared with the
source at direction pairs off the file's grid; the errors go into the report. A table
without measurements near an incident angle the file holds (0 to 85 degrees) cannot be
resampled: FormatError, nothing written.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from patina.errors import FormatError
from patina.export.rgb_upsampling import WAVELENGTHS, upsample
from patina.fitting.samples import table_samples
from patina.progress import Progress
from patina.table.colour_matching import xyz_to_linear_srgb, xyz_weights
from patina.table.formats.resample import relative_error
from patina.table.formats.rgl import error_pairs
from patina.table.formats.rgl_brdf import RglBrdf
from patina.table.formats.rgl_writer import RglLayout, rgl_arrays
from patina.table.formats.tensor_file import parse_tensor_file, tensor_file_bytes, write_tensor_file
from patina.table.spectral import as_linear_srgb

# spectral: pbrt-v4 and Mitsuba's spectral variants; rgb: Mitsuba's RGB variants (which refuse a
# file holding spectra)
CHANNELS = ("spectral", "rgb")
# an incident angle the file holds with no measured sample within this many degrees is a hole
HOLE_DEG = 10.0
CHECK_PAIRS = 8192
CHECK_MAX_THETA_O_DEG = 80.0  # the check leaves out grazing exits, where the format's tail is loose
ANISOTROPIC_PHI_I = 17  # phi_i knots over [-180, 180] deg for an anisotropic source (22.5 deg apart)
ISOTROPY_TOLERANCE = 1e-3  # relative change of the values under a turn about the normal

Evaluate = Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass
class RglSource:
    path: str  # named in messages
    rgb: Evaluate  # (n, 3), (n, 3) -> (n, 3) linear sRGB, 1/sr
    spectral: Evaluate | None = None  # a spectral table's own values at `wavelengths`
    wavelengths: np.ndarray | None = None
    incidences_deg: np.ndarray | None = None  # incident angles with measured samples; None: defined everywhere


def table_source(brdf: Any, path: str) -> RglSource:
    """A Brdf (any format load_brdf reads): its values by its own interpolation."""
    rgb_table = as_linear_srgb(brdf)
    wi, _, _, _ = table_samples(rgb_table, max_theta_deg=89.9)
    incidences = np.degrees(np.arccos(np.clip(wi[:, 2].astype(np.float64), -1, 1)))

    def rgb(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        return np.asarray(rgb_table.eval(wi, wo), np.float64)

    spectral = None
    if brdf.channel_kind == "spectral":
        spectral = lambda wi, wo: np.asarray(brdf.eval(wi, wo), np.float64)  # noqa: E731
    wavelengths = None if spectral is None else np.asarray(brdf.wavelengths, np.float64)
    return RglSource(path, rgb, spectral, wavelengths, incidences)


def check_incidence(source: RglSource, layout: RglLayout) -> None:
    """FormatError when an incident angle the file holds has no measured sample near it."""
    if source.incidences_deg is None:
        return
    if source.incidences_deg.size == 0:
        raise FormatError(source.path, "table", "no measured values: nothing to resample")
    needed = np.linspace(0.0, layout.max_theta_i_deg, layout.theta_i)
    have = np.unique(np.round(source.incidences_deg, 3))
    gaps = np.array([np.min(np.abs(have - t)) for t in needed])
    if np.any(gaps > HOLE_DEG):
        holes = needed[gaps > HOLE_DEG]
        raise FormatError(
            source.path,
            "incident angles",
            f"no measured values within {HOLE_DEG:g} deg of incidence {', '.join(f'{t:.3g}' for t in holes)} deg "
            f"(the table has {have.min():.3g} to {have.max():.3g} deg): an RGL file holds 0 to "
            f"{layout.max_theta_i_deg:g} deg and cannot be resampled from it",
        )


def is_isotropic(evaluate: Evaluate) -> bool:
    """The values unchanged (to ISOTROPY_TOLERANCE) when both directions turn about the normal."""
    wi, wo = error_pairs(512, seed=5)
    turn = 1.1
    c, s = math.cos(turn), math.sin(turn)
    rot = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    a, b = evaluate(wi, wo), evaluate(wi @ rot.T, wo @ rot.T)
    scale = max(float(np.abs(a).max()), 1e-12)
    return bool(np.max(np.abs(a - b)) <= ISOTROPY_TOLERANCE * scale)


def default_layout(source: RglSource) -> RglLayout:
    return RglLayout() if is_isotropic(source.rgb) else RglLayout(phi_i=ANISOTROPIC_PHI_I)


def _spectral_to_rgb(wavelengths: np.ndarray) -> np.ndarray:
    return xyz_to_linear_srgb() @ xyz_weights(wavelengths)  # (3, C): as the RGL reader converts


def rgl_file_arrays(
    source: RglSource, channels: str = "spectral", layout: RglLayout | None = None, description: str = ""
) -> dict[str, np.ndarray]:
    """The file's fields. Upsampled spectra are those of the stored RGB values (the
    upsampling is linear in a colour's scale); a spectral table's RGB is its spectra
    through the CIE observer (linear in the values)."""
    layout = layout or default_layout(source)
    check_incidence(source, layout)
    if source.spectral is not None:
        arrays = rgl_arrays(source.spectral, source.wavelengths, layout=layout, description=description)
        if channels == "rgb":
            stored = arrays.pop("spectra").astype(np.float64)
            del arrays["wavelengths"]
            rgb = np.einsum("kc,pqchw->pqkhw", _spectral_to_rgb(source.wavelengths), stored)
            arrays["rgb"] = rgb.astype(np.float32)
        return arrays
    arrays = rgl_arrays(source.rgb, layout=layout, description=description)
    if channels == "spectral":
        rgb = arrays.pop("rgb").astype(np.float64)  # (phi_i, theta_i, 3, H, W)
        flat = np.moveaxis(rgb, 2, -1).reshape(-1, 3)
        spectra = upsample(flat).reshape(*rgb.shape[:2], *rgb.shape[3:], WAVELENGTHS.size)
        arrays["wavelengths"] = WAVELENGTHS.astype(np.float32)
        arrays["spectra"] = np.moveaxis(spectra, -1, 2).astype(np.float32)
    return arrays


def check_pairs(max_theta_i_deg: float) -> tuple[np.ndarray, np.ndarray]:
    wi, wo = error_pairs(CHECK_PAIRS, seed=31)
    keep = (wi[:, 2] >= math.cos(math.radians(max_theta_i_deg))) & (
        wo[:, 2] >= math.cos(math.radians(CHECK_MAX_THETA_O_DEG))
    )
    return wi[keep], wo[keep]


def read_back_errors(arrays: dict[str, np.ndarray], source: RglSource, name: str) -> dict[str, float]:
    """The written fields read back by Patina's RGL evaluator (spectra through the CIE
    observer) against the source in linear sRGB: relative error median, 95th percentile.
    The file holds f cos(theta_o), which that evaluator divides out again."""
    wi, wo = check_pairs(float(np.degrees(arrays["theta_i"][-1])))
    brdf = RglBrdf(parse_tensor_file(name, tensor_file_bytes(arrays)))
    err = relative_error(brdf.eval(wi, wo), source.rgb(wi, wo))
    return {"relative_error_median": err["median"], "relative_error_p95": err["p95"], "pairs": len(wi)}


def write_rgl_file(
    source: RglSource,
    out: str,
    channels: str = "spectral",
    layout: RglLayout | None = None,
    description: str = "",
    progress: bool = False,
) -> dict[str, Any]:
    """Writes the source as an RGL file at `out` (atomically) after reading it back; returns
    the report: what was written and its errors against the source."""
    if channels not in CHANNELS:
        raise ValueError(f"channels '{channels}': expected one of {', '.join(CHANNELS)}")
    description = description or f"written by Patina from {source.path}"
    layout = layout or default_layout(source)
    check_incidence(source, layout)  # before the progress bar: bad input is one line
    with Progress(3, "writing the RGL tensor file", unit="step", enabled=progress) as bar:
        arrays = rgl_file_arrays(source, channels, layout, description)
        bar.update(1)
        errors = read_back_errors(arrays, source, out)
        bar.update(2)
        write_tensor_file(out, arrays)
        bar.update(3)
    wavelengths = arrays.get("wavelengths")
    return {
        "out": out,
        "source": source.path,
        "isotropic": arrays["phi_i"].size <= 1,
        "theta_i_deg": [0.0, float(np.degrees(arrays["theta_i"][-1]))],
        "incident_angles": int(arrays["theta_i"].size) * int(arrays["phi_i"].size),
        "channels": [k for k in ("rgb", "spectra") if k in arrays],
        "wavelengths_nm": None
        if wavelengths is None
        else [float(wavelengths[0]), float(wavelengths[-1]), int(wavelengths.size)],
        "spectra_from": None
        if "spectra" not in arrays
        else ("the table's own spectra" if source.spectral is not None else "RGB, Jakob-Hanika (Mitsuba's table)"),
        "read_back_error": errors,
    }
