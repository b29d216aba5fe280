"""Writes a BRDF given as a function into an RGL .bsdf tensor file (tensor_file v1.0), by
the construction of Dupuy & Jakob 2018 (section 5): an NDF table, the projected area
sigma(wi) it implies, one VNDF warp per incident direction, and the BRDF stored at the
nodes of the warped (sample) domain, divided by ndf / (4 sigma) (the `jacobian` flag set),
with its luminance as the second warp for sampling.

Evaluating the written file by the format's rule (rgl_brdf.py) gives f back exactly at
the nodes and bilinearly between them. The NDF defaults to the BRDF's own backscatter,
D(m) ~ Y(f(m, m)) cos^2 theta_m, the first step of the paper's NDF estimation; an
analytic model passes its NDF for a tighter fit.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from patina.table.angles import angles_to_directions
from patina.table.formats.rgl_brdf import phi_to_u, theta_to_u, u_to_phi, u_to_theta
from patina.table.formats.rgl_warp import Interpolant2D
from patina.table.formats.tensor_file import write_tensor_file

BrdfFunction = Callable[[np.ndarray, np.ndarray], np.ndarray]  # (N, 3), (N, 3) -> (N, channels)
NdfFunction = Callable[[np.ndarray], np.ndarray]  # (N, 3) microfacet normals -> (N,)
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])  # linear sRGB -> Y (Rec. 709)
SIGMA_QUADRATURE = (96, 192)  # theta_m x phi_m nodes of the projected-area integral


@dataclass
class RglLayout:
    """Grid sizes of the written file: (rows = phi, columns = theta) for each 2-D table."""

    theta_i: int = 12  # evenly spaced in angle up to max_theta_i_deg
    phi_i: int = 1  # 1: isotropic; otherwise knots over [-pi, pi]
    ndf: tuple[int, int] = (16, 64)
    sigma: tuple[int, int] = (16, 32)
    vndf: tuple[int, int] = (32, 64)
    values: tuple[int, int] = (32, 32)
    max_theta_i_deg: float = 85.0


def _unit_grid(rows: int, cols: int) -> np.ndarray:
    """(rows * cols, 2) points (x = column, y = row) at the nodes of a grid over [0, 1]^2, C order."""
    y, x = np.meshgrid(np.linspace(0, 1, rows), np.linspace(0, 1, cols), indexing="ij")
    return np.stack([x.ravel(), y.ravel()], axis=1)


def _direction(u: np.ndarray, phi_offset: np.ndarray | float = 0.0) -> np.ndarray:
    return angles_to_directions(u_to_theta(u[:, 0]), u_to_phi(u[:, 1]) + phi_offset)


def backscatter_ndf(brdf: BrdfFunction) -> NdfFunction:
    def ndf(m: np.ndarray) -> np.ndarray:
        value = np.asarray(brdf(m, m), dtype=np.float64)
        y = value @ LUMINANCE if value.shape[1] == 3 else value.mean(axis=1)
        return np.maximum(y, 0.0) * np.clip(m[:, 2], 0, 1) ** 2

    return ndf


def rgl_arrays(
    brdf: BrdfFunction,
    wavelengths: np.ndarray | None = None,
    ndf: NdfFunction | None = None,
    layout: RglLayout | None = None,
    description: str = "written by Patina",
) -> dict[str, np.ndarray]:
    """The fields of an RGL file of `brdf` (RGB, or spectral at `wavelengths` nm). The values
    stored are f cos(theta_o) (theta_o of the direction the file is not conditioned on), what
    the format's own readers return (brdf-loader's `eval`, "f_r * cos"; Mitsuba 3's
    `measured`, whose `eval` includes the cosine as every Mitsuba BSDF's does); Patina's
    reader (rgl_brdf) divides it out again."""
    layout = layout or RglLayout()
    ndf = ndf or backscatter_ndf(brdf)
    isotropic = layout.phi_i <= 1
    theta_i = np.radians(np.linspace(0.0, layout.max_theta_i_deg, layout.theta_i))
    phi_i = np.zeros(1) if isotropic else np.linspace(-math.pi, math.pi, layout.phi_i)

    # the NDF on its grid, floored so that the division below stays finite, normalised
    nodes = _unit_grid(*layout.ndf)
    d = np.maximum(ndf(_direction(nodes)), 0.0)
    d = np.maximum(d, 1e-4 * d.max() if d.max() > 0 else 1.0)
    ndf_table = Interpolant2D(d.reshape(layout.ndf))
    # projected area sigma(wi) = integral of D(m) <wi, m> over the hemisphere (midpoint rule in u)
    nt, npq = SIGMA_QUADRATURE
    ut, up = (np.arange(nt) + 0.5) / nt, (np.arange(npq) + 0.5) / npq
    q = np.stack([g.ravel() for g in np.meshgrid(ut, up, indexing="ij")], axis=1)
    m_q = _direction(q)
    weight = ndf_table.eval(q) * np.sin(u_to_theta(q[:, 0])) * math.pi * q[:, 0] * (2 * math.pi) / (nt * npq)
    scale = 1.0 / np.sum(weight * m_q[:, 2])  # so that the NDF projects to the unit disc
    ndf_table = Interpolant2D(d.reshape(layout.ndf) * scale)
    weight *= scale
    s_nodes = _unit_grid(*layout.sigma)
    wi_s = _direction(s_nodes)
    sigma = np.maximum(wi_s @ m_q.T, 0.0) @ weight
    sigma_table = Interpolant2D(sigma.reshape(layout.sigma))

    vndf = np.empty((phi_i.size, theta_i.size, *layout.vndf))
    v_nodes = _unit_grid(*layout.vndf)
    for p, ph in enumerate(phi_i):
        for t, th in enumerate(theta_i):
            wi = angles_to_directions(th, ph)
            m = _direction(v_nodes, ph if isotropic else 0.0)
            jac = 2 * math.pi**2 * v_nodes[:, 0] * np.sin(u_to_theta(v_nodes[:, 0]))  # dm / du
            v = ndf_table.eval(v_nodes) * np.maximum(m @ wi, 0.0) * jac
            vndf[p, t] = np.maximum(v, 1e-6 * v.max()).reshape(layout.vndf)
    vndf_warp = Interpolant2D(vndf, [phi_i, theta_i], warp=True)

    channels = 3 if wavelengths is None else len(wavelengths)
    values = np.zeros((phi_i.size, theta_i.size, channels, *layout.values))
    luminance = np.empty((phi_i.size, theta_i.size, *layout.values))
    s = _unit_grid(*layout.values)
    for p, ph in enumerate(phi_i):
        for t, th in enumerate(theta_i):
            n = len(s)
            u_m, _ = vndf_warp.sample(s, [np.full(n, ph), np.full(n, th)])
            m = _direction(u_m, ph if isotropic else 0.0)
            wi = np.repeat(angles_to_directions(th, ph)[None, :], n, axis=0)
            wo = 2.0 * np.sum(m * wi, axis=1, keepdims=True) * m - wi
            above = wo[:, 2] > 0
            f = np.zeros((n, channels))
            if above.any():
                f[above] = brdf(wi[above], wo[above]) * wo[above, 2:3]
            u_m_rel = np.stack([u_m[:, 0], u_m[:, 1]], axis=1)
            u_wi = np.stack([theta_to_u(np.full(n, th)), phi_to_u(np.full(n, ph))], axis=1)
            stored = f * (4.0 * sigma_table.eval(u_wi) / ndf_table.eval(u_m_rel))[:, None]
            values[p, t] = stored.T.reshape(channels, *layout.values)
            y = stored @ LUMINANCE if channels == 3 else stored.mean(axis=1)
            luminance[p, t] = np.maximum(y, 1e-6 * max(float(y.max()), 1e-30)).reshape(layout.values)

    arrays: dict[str, np.ndarray] = {
        "description": np.frombuffer(description.encode("utf-8"), dtype=np.uint8),
        "theta_i": theta_i.astype(np.float32),
        "phi_i": phi_i.astype(np.float32),
        "ndf": (d.reshape(layout.ndf) * scale).astype(np.float32),
        "sigma": sigma.reshape(layout.sigma).astype(np.float32),
        "vndf": vndf.astype(np.float32),
        "luminance": luminance.astype(np.float32),
        "jacobian": np.array([1], dtype=np.uint8),
    }
    if wavelengths is None:
        arrays["rgb"] = values.astype(np.float32)
    else:
        arrays["wavelengths"] = np.asarray(wavelengths, dtype=np.float32)
        arrays["spectra"] = values.astype(np.float32)
    return arrays


def write_rgl(
    path: str | os.PathLike[str],
    brdf: BrdfFunction,
    wavelengths: np.ndarray | None = None,
    ndf: NdfFunction | None = None,
    layout: RglLayout | None = None,
    description: str = "written by Patina",
) -> None:
    """Writes `brdf` as an RGL .bsdf file (atomically)."""
    write_tensor_file(path, rgl_arrays(brdf, wavelengths, ndf, layout, description))
