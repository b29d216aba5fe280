"""A luminaire: its photometry (patina.photometry) and the candela table as a `_core.Grid2`,
evaluated by the same coherent search and bilinear interpolation as the BRDF tables.

    lum = patina.load_luminaire("materials/luminaires/downlight.ies")
    lum.intensity(theta, phi)      # candela; radians: type C theta = gamma, phi = C;
                                   #                  type B theta = V, phi = H
    lum.intensity_at(directions)   # unit vectors in the luminaire's frame (docs/luminaires.md)
    lum.flux(); lum.info(); lum.grid()

`flux()` integrates the interpolated table exactly: the table is bilinear in (h, v), so the
integral over each cell of I dOmega (dOmega = sin(gamma) dgamma dC for type C, cos(H) dH dV
for type B) is a weighted sum of the four corner values with closed-form weights. The only
error left is floating-point rounding (relative < 1e-8), not a quadrature error.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from patina.errors import FormatError
from patina.native import _core
from patina.photometry.angles import angles_of
from patina.photometry.model import Photometry
from patina.photometry.reading import read_photometry


def _segment_weights(knots: np.ndarray, density: str) -> np.ndarray:
    """w[i] = integral of the piecewise-linear hat function of knot i times the density
    (1, sin or cos of the angle) over the axis; knots in radians."""
    w = np.zeros(len(knots))
    a, b = knots[:-1], knots[1:]
    h = b - a
    if density == "one":
        w[:-1] += h / 2
        w[1:] += h / 2
        return w
    if density == "sin":
        # integral of sin over [a, b] weighted by (x - a)/h and (b - x)/h
        w_b = (np.sin(b) - np.sin(a) - h * np.cos(b)) / h
        w_a = (np.cos(a) - np.cos(b)) - w_b
    else:  # cos
        w_b = (np.cos(b) - np.cos(a) + h * np.sin(b)) / h
        w_a = (np.sin(b) - np.sin(a)) - w_b
    w[:-1] += w_a
    w[1:] += w_b
    return w


class Luminaire:
    """A photometric file ready to evaluate; see the module docstring."""

    def __init__(self, photometry: Photometry) -> None:
        self.photometry = photometry
        self.kind = photometry.type
        self._h = np.radians(photometry.h_deg).astype(np.float32)
        self._v = np.radians(photometry.v_deg).astype(np.float32)
        if np.any(np.diff(self._h) <= 0) or np.any(np.diff(self._v) <= 0):
            raise FormatError(photometry.path, "", "two angles of the table are closer than float32 can tell apart")
        self._candela = np.ascontiguousarray(photometry.candela, np.float32)
        self._table = _core.Grid2(self._h, self._v, self._candela)

    @property
    def path(self) -> str:
        return self.photometry.path

    @property
    def table(self) -> _core.Grid2:
        """The candela table over (h, v) in radians, as the native kernels read it."""
        return self._table

    def grid(self) -> tuple[str, np.ndarray, np.ndarray, np.ndarray]:
        """(kind "C" or "B", h knots in radians, v knots in radians, candela (n_h, n_v)), all float32."""
        return self.kind, self._h.copy(), self._v.copy(), self._candela.copy()

    def intensity(self, theta: Any, phi: Any, width: int = 0) -> np.ndarray:
        """Candela at the photometric angles (radians): type C theta = gamma, phi = C (any
        real; taken mod 2 pi); type B theta = V (taken into (-pi, pi]), phi = H."""
        theta, phi = np.broadcast_arrays(np.asarray(theta, np.float64), np.asarray(phi, np.float64))
        shape = theta.shape
        if self.kind == "C":
            h, v = np.mod(phi, 2 * np.pi), theta
        else:
            h, v = phi, np.pi - np.mod(np.pi - theta, 2 * np.pi)
        out = self._table.eval(
            np.ascontiguousarray(h.ravel(), np.float32), np.ascontiguousarray(v.ravel(), np.float32), width
        )
        return np.asarray(out, np.float32).reshape(shape)

    def intensity_at(self, directions: Any, width: int = 0) -> np.ndarray:
        """Candela towards directions (..., 3) in the luminaire's frame."""
        h, v = angles_of(directions, self.kind)
        return self.intensity(v, h, width)

    def flux(self) -> float:
        """Lumens: the interpolated table integrated exactly over the sphere (module docstring)."""
        h = self._h.astype(np.float64)
        v = self._v.astype(np.float64)
        if self.kind == "C":
            wh, wv = _segment_weights(h, "one"), _segment_weights(v, "sin")
        else:
            wh, wv = _segment_weights(h, "cos"), _segment_weights(v, "one")
        return float(wh @ self._candela.astype(np.float64) @ wv)

    def _plane(self, name: str, step_deg: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
        """Intensities round a great circle: signed angle s in degrees from the reference direction."""
        s = np.arange(-180.0, 180.0 + step_deg / 2, step_deg)
        a = np.radians(np.abs(s))
        if self.kind == "C":
            c0 = {"C0-C180": 0.0, "C90-C270": 90.0}[name]
            phi = np.radians(np.where(s >= 0, c0, c0 + 180.0))
            return s, self.intensity(a, phi)
        if name == "vertical":  # H = 0, V round the full circle
            return s, self.intensity(np.radians(s), np.zeros_like(s))
        # horizontal: V = 0 for |s| <= 90, else through the back (V = 180)
        hh = np.where(np.abs(s) <= 90, s, np.sign(s) * 180.0 - s)
        vv = np.where(np.abs(s) <= 90, 0.0, 180.0)
        return s, self.intensity(np.radians(vv), np.radians(hh))

    def planes(self) -> tuple[str, str]:
        return ("C0-C180", "C90-C270") if self.kind == "C" else ("horizontal", "vertical")

    def spread(self, name: str, fraction: float) -> float | None:
        """Full angle in degrees between the two directions of the plane where the intensity
        falls to `fraction` of the plane's maximum (beam 0.5, field 0.1); None if dark or never reached."""
        s, values = self._plane(name)
        peak = int(np.argmax(values))
        top = float(values[peak])
        if top <= 0:
            return None
        level = fraction * top
        n = len(s)
        edges = []
        for step in (1, -1):
            i = peak
            for _ in range(n - 1):
                j = (i + step) % n
                if values[j] < level:
                    t = (values[i] - level) / (values[i] - values[j])
                    edges.append(step * (abs(i - peak) + t))
                    break
                i = j
            else:
                return None
        width = (edges[0] - edges[1]) * (s[1] - s[0])
        return float(width) if width < 360 else None

    def info(self) -> dict[str, Any]:
        p = self.photometry
        flux = self.flux()
        i, j = np.unravel_index(int(np.argmax(p.candela)), p.candela.shape)
        beam = {name: self.spread(name, 0.5) for name in self.planes()}
        field = {name: self.spread(name, 0.1) for name in self.planes()}
        return {
            "source": os.path.abspath(p.path),
            "format": p.format,
            "version": p.version,
            "type": p.type,
            "symmetry": p.symmetry,
            "file_angles": {
                "horizontal": {
                    "count": len(p.file_h_deg),
                    "min_deg": float(p.file_h_deg[0]),
                    "max_deg": float(p.file_h_deg[-1]),
                },
                "vertical": {
                    "count": len(p.file_v_deg),
                    "min_deg": float(p.file_v_deg[0]),
                    "max_deg": float(p.file_v_deg[-1]),
                },
            },
            "grid": {"horizontal": len(p.h_deg), "vertical": len(p.v_deg)},
            "lamps": p.lamps,
            "absolute_photometry": p.lumens is None,
            "lumens_declared": p.lumens,
            "luminaire_lumens_declared": p.luminaire_lumens,
            "lumens_integrated": flux,
            "light_output_ratio": None if not p.lumens else flux / p.lumens,
            "light_output_ratio_declared": (
                None if not (p.lumens and p.luminaire_lumens) else p.luminaire_lumens / p.lumens
            ),
            "multiplier": p.multiplier,
            "max_candela": float(p.candela[i, j]),
            "max_at_deg": {"horizontal": float(p.h_deg[i]), "vertical": float(p.v_deg[j])},
            "beam_angle_deg": beam,
            "field_angle_deg": field,
            "tilt": None
            if p.tilt is None
            else {
                "geometry": p.tilt.geometry,
                "angles_deg": p.tilt.angles_deg.tolist(),
                "factors": p.tilt.factors.tolist(),
            },
            "opening_m": {
                "width": p.opening.width,
                "length": p.opening.length,
                "height": p.opening.height,
                "shape": p.opening.shape,
            },
            "input_watts": p.input_watts,
            "manufacturer": p.manufacturer,
            "catalogue": p.catalogue,
            "luminaire": p.luminaire,
            "keywords": dict(p.keywords),
            "warnings": list(p.warnings),
        }


def load_luminaire(path: str | os.PathLike) -> Luminaire:
    """Reads an IES LM-63 (.ies) or EULUMDAT (.ldt) file; bad files raise FormatError."""
    return Luminaire(read_photometry(path))
