"""An RGL .bsdf material (Dupuy & Jakob 2018) evaluated by the format's own rule, in double
precision: the reference a native evaluator is checked against, and what the .bsdf reader
resamples onto a Patina table.

f(wi, wo), for wi and wo above the surface:
  m = normalize(wi + wo); theta, phi of wi and m;
  u_wi = (sqrt(2 theta_i / pi), (phi_i + pi) / 2 pi), u_m likewise (phi_m - phi_i for an
  isotropic file, wrapped into [0, 1));
  s = the inverse VNDF warp of u_m, conditioned on (phi_i, theta_i);
  f = spectra(s | phi_i, theta_i, channel), times ndf(u_m) / (4 sigma(u_wi)) when the
  file's `jacobian` flag is set (Mitsuba 3's `measured` plugin).
Files of reduced azimuthal range (phi_i over pi or pi/2) are mirrored into it first.
Negative values (the acquisition's spectra out of gamut) are clamped to 0 as
brdf-loader's RGB evaluator does.
"""

from __future__ import annotations

import math

import numpy as np

from patina.errors import FormatError
from patina.table.colour_matching import xyz_to_linear_srgb, xyz_weights
from patina.table.formats.rgl_warp import Interpolant2D
from patina.table.formats.tensor_file import TensorFile, read_tensor_file

ANGLE_SLACK = 1e-3  # rad: incident-angle axes may overshoot [0, pi/2] / [-pi, pi] by float rounding


def theta_to_u(theta: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(theta, 0.0) * (2.0 / math.pi))


def u_to_theta(u: np.ndarray) -> np.ndarray:
    return u * u * (math.pi / 2.0)


def phi_to_u(phi: np.ndarray) -> np.ndarray:
    return (phi + math.pi) / (2.0 * math.pi)


def u_to_phi(u: np.ndarray) -> np.ndarray:
    return (2.0 * u - 1.0) * math.pi


def elevation(d: np.ndarray) -> np.ndarray:
    """acos(z) without its loss of precision near the pole."""
    dist = np.sqrt(d[:, 0] ** 2 + d[:, 1] ** 2 + (d[:, 2] - 1.0) ** 2)
    return 2.0 * np.arcsin(np.clip(0.5 * dist, 0.0, 1.0))


class RglBrdf:
    """The fields of an RGL file, checked, with `eval` (N pairs at once)."""

    def __init__(self, tf: TensorFile) -> None:
        self.path = tf.path
        self.description = ""
        if "description" in tf.fields:
            self.description = bytes(tf.array("description").astype(np.uint8)).decode("utf-8", "replace").strip()
        theta_i = self._array(tf, "theta_i", 1)
        phi_i = self._array(tf, "phi_i", 1)
        ndf = self._array(tf, "ndf", 2)
        sigma = self._array(tf, "sigma", 2)
        vndf = self._array(tf, "vndf", 4)
        luminance = self._array(tf, "luminance", 4)
        if "spectra" in tf.fields:
            self.channel_kind, values = "spectral", self._array(tf, "spectra", 5)
            self.wavelengths = self._array(tf, "wavelengths", 1)
            self._increasing(tf, "wavelengths", self.wavelengths, 1.0, 1e5)
            if values.shape[2] != self.wavelengths.size:
                raise tf.fail("spectra", f"{values.shape[2]} channels but {self.wavelengths.size} wavelengths")
        elif "rgb" in tf.fields:
            self.channel_kind, values, self.wavelengths = "rgb", self._array(tf, "rgb", 5), None
            if values.shape[2] != 3:
                raise tf.fail("rgb", f"shape {list(values.shape)}: the third dimension must be 3 (R, G, B)")
        else:
            raise FormatError(tf.path, "field table", "neither an 'rgb' nor a 'spectra' field: no reflectance data")
        if "jacobian" not in tf.fields:
            raise FormatError(tf.path, "field table", "no 'jacobian' field")
        jacobian = tf.array("jacobian")
        if jacobian.dtype != np.uint8 or jacobian.shape != (1,):
            raise tf.fail("jacobian", f"{jacobian.dtype} of shape {list(jacobian.shape)}: expected one uint8")
        self.jacobian = bool(jacobian[0])
        self._increasing(tf, "theta_i", theta_i, -ANGLE_SLACK, math.pi / 2 + ANGLE_SLACK)
        self._increasing(tf, "phi_i", phi_i, -math.pi - ANGLE_SLACK, math.pi + ANGLE_SLACK)
        lead = (phi_i.size, theta_i.size)
        for name, a in (("vndf", vndf), ("luminance", luminance), ("spectra/rgb", values)):
            if a.shape[:2] != lead:
                raise tf.fail(
                    name.split("/")[-1] if name != "spectra/rgb" else self._values_name(),
                    f"shape {list(a.shape)}: must begin with (phi_i, theta_i) = {list(lead)}",
                )
        if values.shape[3:] != luminance.shape[2:]:
            raise tf.fail(
                self._values_name(),
                f"grid {list(values.shape[3:])} differs from luminance's {list(luminance.shape[2:])}",
            )
        for name, a in (("ndf", ndf), ("sigma", sigma), ("vndf", vndf), ("luminance", luminance)):
            if a.shape[-1] < 2 or a.shape[-2] < 2:
                raise tf.fail(name, f"shape {list(a.shape)}: each grid needs at least 2 x 2 nodes")
            if np.any(a < 0):
                first = np.unravel_index(int(np.argmax(a < 0)), a.shape)
                raise tf.fail(name, f"negative value {a[first]:g} at index {list(map(int, first))}")
        if not np.all(sigma > 0):
            raise tf.fail("sigma", "a projected area of 0: every value must be positive")
        if values.shape[-1] < 2 or values.shape[-2] < 2:
            raise tf.fail(self._values_name(), f"shape {list(values.shape)}: each grid needs at least 2 x 2 nodes")
        self.isotropic = phi_i.size <= 2
        self.reduction = 1
        if not self.isotropic:
            self.reduction = round(2 * math.pi / (phi_i[-1] - phi_i[0]))
            if self.reduction not in (1, 2, 4):
                raise tf.fail("phi_i", f"spans {math.degrees(phi_i[-1] - phi_i[0]):.4g} deg: expected 360, 180 or 90")
        if self.channel_kind == "spectral":
            try:
                matrix = self._rgb_matrix()
            except ValueError as e:
                raise tf.fail("wavelengths", str(e)) from None
            values = np.einsum("kc,pqchw->pqkhw", matrix, values)
            self.source_channels = (
                f"{self.wavelengths.size} wavelengths {self.wavelengths[0]:g}-{self.wavelengths[-1]:g} nm"
            )
        else:
            self.source_channels = self.channel_kind
        self.channels = values.shape[2]
        self.theta_i, self.phi_i = theta_i, phi_i
        try:
            self.ndf = Interpolant2D(ndf)
            self.sigma = Interpolant2D(sigma)
            self.vndf = Interpolant2D(vndf, [phi_i, theta_i], warp=True)
            self.luminance = Interpolant2D(luminance, [phi_i, theta_i], warp=True)
            self.values = Interpolant2D(values, [phi_i, theta_i, np.arange(self.channels, dtype=np.float64)])
        except (ValueError, FloatingPointError, ZeroDivisionError) as e:
            raise FormatError(tf.path, "vndf/luminance", str(e)) from None
        if not (np.all(np.isfinite(self.vndf.marginal)) and np.all(np.isfinite(self.luminance.marginal))):
            raise FormatError(
                tf.path, "vndf/luminance", "a distribution that is zero everywhere for some incident angle"
            )

    def _values_name(self) -> str:
        return "spectra" if self.channel_kind == "spectral" else "rgb"

    @staticmethod
    def _array(tf: TensorFile, name: str, rank: int) -> np.ndarray:
        if name not in tf.fields:
            raise FormatError(
                tf.path,
                "field table",
                f"no '{name}' field (an RGL material has theta_i, phi_i, "
                "ndf, sigma, vndf, luminance, rgb or spectra, jacobian)",
            )
        f = tf.fields[name]
        if f.dtype != np.dtype("<f4"):
            raise tf.fail(name, f"dtype {f.dtype.name}: expected float32")
        if len(f.shape) != rank:
            raise tf.fail(name, f"shape {list(f.shape)}: expected {rank} dimensions")
        a = tf.array(name).astype(np.float64)
        if not np.all(np.isfinite(a)):
            first = np.unravel_index(int(np.argmax(~np.isfinite(a))), a.shape)
            raise tf.fail(name, f"value {a[first]} at index {list(map(int, first))} is not finite")
        return a

    @staticmethod
    def _increasing(tf: TensorFile, name: str, a: np.ndarray, lo: float, hi: float) -> None:
        if a.size < 1 or np.any(np.diff(a) <= 0) or a[0] < lo or a[-1] > hi:
            raise tf.fail(name, f"values must increase strictly within [{lo:.4g}, {hi:.4g}]")

    def _rgb_matrix(self) -> np.ndarray:
        return xyz_to_linear_srgb() @ xyz_weights(self.wavelengths)

    # --- evaluation
    def _fold(self, wi: np.ndarray, *others: np.ndarray) -> tuple[np.ndarray, ...]:
        """Mirrors the pairs into the azimuthal range a reduced file holds (Mitsuba's rule)."""
        if self.reduction < 2:
            return (wi, *others)
        sy = np.where(wi[:, 1] >= 0, -1.0, 1.0)
        sx = np.where(wi[:, 0] >= 0, -1.0, 1.0) if self.reduction == 4 else sy
        flip = np.stack([sx, sy, np.ones_like(sx)], axis=1)
        return tuple(d * flip for d in (wi, *others))

    def eval(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        """f(wi, wo) (N, channels) in 1/sr for unit directions (N, 3); 0 below the horizon."""
        wi = np.asarray(wi, dtype=np.float64).reshape(-1, 3)
        wo = np.asarray(wo, dtype=np.float64).reshape(-1, 3)
        above = (wi[:, 2] > 0) & (wo[:, 2] > 0)
        out = np.zeros((len(wi), self.channels))
        if not above.any():
            return out
        a, b = self._fold(wi[above], wo[above])
        m = a + b
        m /= np.linalg.norm(m, axis=1, keepdims=True)
        theta_i, phi_i = elevation(a), np.arctan2(a[:, 1], a[:, 0])
        theta_m, phi_m = elevation(m), np.arctan2(m[:, 1], m[:, 0])
        u_wi = np.stack([theta_to_u(theta_i), phi_to_u(phi_i)], axis=1)
        u_m = np.stack([theta_to_u(theta_m), phi_to_u(phi_m - phi_i if self.isotropic else phi_m)], axis=1)
        u_m[:, 1] -= np.floor(u_m[:, 1])
        params = [phi_i, theta_i]
        s, _ = self.vndf.invert(u_m, params)
        value = np.stack(
            [self.values.eval(s, [phi_i, theta_i, np.full(len(s), float(c))]) for c in range(self.channels)], axis=1
        )
        if self.jacobian:
            value *= (self.ndf.eval(u_m) / (4.0 * self.sigma.eval(u_wi)))[:, None]
        # the file holds f cos(theta_o), as the format's own readers return it (brdf-loader's
        # eval, "f_r * cos"; Mitsuba 3's measured, whose eval includes the cosine): f is that
        # over cos(theta_o) (the fold flips only x and y)
        out[above] = np.maximum(value, 0.0) / b[:, 2:3]
        return out


def read_rgl_brdf(path: str) -> RglBrdf:
    """The file checked and ready to evaluate; FormatError (file, field, problem) otherwise."""
    tf = read_tensor_file(path)
    try:
        return RglBrdf(tf)
    except MemoryError:
        raise FormatError(path, "file", "not enough memory to read this file") from None
