"""The Günther et al. (2005) multi-lobe car-paint model, and the base table a clear coat goes over.

J. Günther, T. Chen, M. Goesele, I. Wald, H.-P. Seidel, "Efficient Acquisition and
Realistic Rendering of Car Paint", Vision, Modeling, and Visualization (VMV) 2005.
The paint is a smooth clear coat over a base whose BRDF is a Lambert term plus three
Cook-Torrance lobes (Beckmann distribution, Schlick Fresnel, Cook-Torrance shadowing);
the base is evaluated at the directions refracted through the coat. The fitted
parameters of eight measured paints are the paper's; `PAINTS` holds them as transcribed
in LuxRender's car-paint presets (LuxRender/Lux, materials/carpaint.h), which is where
they were read for Patina (see materials/carpaint-base.md).

Patina's renderer puts its own coat (Fresnel reflection, eta 1.5) over a base table
and attenuates the table by (1 - F(cos_i)) (1 - F(cos_o)) at the *outside* directions.
`coated_base` is what that table must hold for coat + table to be the published model:
the base BRDF at the refracted directions, as a function of the outside directions.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from patina.synthetic.analytic import BrdfFunction, direction_pairs

CLEAR_COAT_ETA = 1.5


@dataclass(frozen=True)
class PaintParameters:
    """One paint of the model: kd RGB (Lambert, f = kd / pi) and per lobe ks RGB, Schlick F0 r, Beckmann m."""

    name: str
    kd: tuple[float, float, float]
    ks: tuple[tuple[float, float, float], tuple[float, float, float], tuple[float, float, float]]
    r: tuple[float, float, float]
    m: tuple[float, float, float]


# Günther et al. 2005, fitted parameters of the measured paints (as in LuxRender's presets).
PAINTS: dict[str, PaintParameters] = {
    p.name: p
    for p in (
        PaintParameters(
            "ford f8",
            (0.0012, 0.0015, 0.0018),
            ((0.0049, 0.0076, 0.0120), (0.0100, 0.0130, 0.0180), (0.0070, 0.0065, 0.0077)),
            (0.15, 0.087, 0.90),
            (0.32, 0.11, 0.013),
        ),
        PaintParameters(
            "polaris silber",
            (0.0550, 0.0630, 0.0710),
            ((0.0650, 0.0820, 0.0880), (0.1100, 0.1100, 0.1300), (0.0080, 0.0130, 0.0150)),
            (1.0, 0.92, 0.90),
            (0.38, 0.17, 0.013),
        ),
        PaintParameters(
            "opel titan",
            (0.0110, 0.0130, 0.0150),
            ((0.0570, 0.0660, 0.0780), (0.1100, 0.1200, 0.1300), (0.0095, 0.0140, 0.0160)),
            (0.85, 0.86, 0.90),
            (0.38, 0.17, 0.014),
        ),
        PaintParameters(
            "bmw339",
            (0.0120, 0.0150, 0.0160),
            ((0.0620, 0.0760, 0.0800), (0.1100, 0.1200, 0.1200), (0.0083, 0.0150, 0.0160)),
            (0.92, 0.87, 0.90),
            (0.39, 0.17, 0.013),
        ),
        PaintParameters(
            "2k acrylack",
            (0.4200, 0.3200, 0.1000),
            ((0.0, 0.0, 0.0), (0.0280, 0.0260, 0.0060), (0.0170, 0.0075, 0.0041)),
            (1.0, 0.90, 0.17),
            (0.88, 0.80, 0.015),
        ),
        PaintParameters(
            "white",
            (0.6100, 0.6300, 0.5500),
            ((2.6e-06, 0.00031, 3.1e-08), (0.0130, 0.0110, 0.0083), (0.0490, 0.0420, 0.0370)),
            (0.049, 0.45, 0.17),
            (1.0, 0.15, 0.015),
        ),
        PaintParameters(
            "blue",
            (0.0079, 0.0230, 0.1000),
            ((0.0011, 0.0015, 0.0019), (0.0250, 0.0300, 0.0430), (0.0590, 0.0740, 0.0820)),
            (1.0, 0.094, 0.17),
            (0.15, 0.043, 0.020),
        ),
        PaintParameters(
            "blue matte",
            (0.0099, 0.0360, 0.1200),
            ((0.0032, 0.0045, 0.0059), (0.1800, 0.2300, 0.2800), (0.0400, 0.0490, 0.0510)),
            (1.0, 0.046, 0.17),
            (0.16, 0.075, 0.034),
        ),
    )
}


def base_brdf(paint: PaintParameters) -> BrdfFunction:
    """The base BRDF at (wi, wo) *inside* the coat (local frame, z = normal); (n, 3) RGB.

    f = kd / pi + sum_j ks_j F_j D_j G / (pi cos_i cos_o) (Cook and Torrance 1982): D_j is
    Beckmann exp(-tan^2 theta_h / m_j^2) / (m_j^2 cos^4 theta_h), F_j is Schlick with F0 = r_j
    at the angle between wi and the half vector, G is Cook-Torrance's V-groove shadowing.
    Symmetric in wi and wo, so reciprocal.
    """
    kd = np.asarray(paint.kd, dtype=np.float64) / np.pi
    ks = np.asarray(paint.ks, dtype=np.float64)  # (3 lobes, 3 channels)
    r = np.asarray(paint.r, dtype=np.float64)
    m2 = np.asarray(paint.m, dtype=np.float64) ** 2

    def f(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        wi, wo, h = direction_pairs(wi, wo)
        ci, co = wi[:, 2], wo[:, 2]
        ch = np.clip(h[:, 2], 1e-12, 1.0)
        vh = np.clip(np.sum(wi * h, axis=1), 1e-12, 1.0)
        cpos_i, cpos_o = np.maximum(ci, 1e-12), np.maximum(co, 1e-12)
        g = np.minimum(1.0, np.minimum(2 * ch * cpos_o / vh, 2 * ch * cpos_i / vh))
        tan2 = (1.0 - ch * ch) / (ch * ch)
        d = np.exp(-tan2[:, None] / m2[None, :]) / (m2[None, :] * ch[:, None] ** 4)  # (n, lobes)
        fresnel = r[None, :] + (1.0 - r[None, :]) * (1.0 - vh[:, None]) ** 5
        weight = d * fresnel * (g / (np.pi * cpos_i * cpos_o))[:, None]  # (n, lobes)
        out = kd[None, :] + weight @ ks
        out[(ci <= 0) | (co <= 0)] = 0.0
        return out

    return f


def refract_in(w: np.ndarray, eta: float = CLEAR_COAT_ETA) -> np.ndarray:
    """Outside directions (n, 3) in the upper hemisphere to the directions refracted into the coat.

    Snell's law keeps the azimuth: sin theta' = sin theta / eta. A direction below the
    horizon maps as its mirror image above it does, which keeps tables continuous there.
    """
    w = np.asarray(w, dtype=np.float64)
    xy = w[:, :2] / eta
    s2 = np.sum(xy * xy, axis=1)
    norm = np.sqrt(np.sum(w * w, axis=1))
    xy = xy / norm[:, None]
    s2 = s2 / (norm * norm)
    return np.concatenate([xy, np.sqrt(np.maximum(1.0 - s2, 0.0))[:, None]], axis=1)


def coated_base(paint: PaintParameters, eta: float = CLEAR_COAT_ETA) -> BrdfFunction:
    """What a base table under a smooth coat of index eta holds: f_base(refract(wi), refract(wo)).

    The renderer adds the coat's mirror reflection F and multiplies this by
    (1 - F(cos_i)) (1 - F(cos_o)), which is Günther et al.'s model as published. Below the
    horizon (z <= 0) it is the mirror image of its values above rather than 0, so a table
    sampled from it interpolates smoothly up to the horizon (Brdf.eval returns 0 there anyway).
    """
    base = base_brdf(paint)

    def f(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        return base(refract_in(wi, eta), refract_in(wo, eta))

    return f


def coated_paint(paint: PaintParameters, eta: float = CLEAR_COAT_ETA) -> BrdfFunction:
    """The published model's glossy part as seen from outside: (1 - F_i)(1 - F_o) f_base(refracted).

    F is the exact unpolarised dielectric Fresnel reflectance; the coat's mirror reflection (a
    delta) is left out. Zero below the horizon.
    """
    inner = coated_base(paint, eta)

    def f(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        wi = np.asarray(wi, dtype=np.float64)
        wo = np.asarray(wo, dtype=np.float64)
        t = (1.0 - dielectric_fresnel(wi[:, 2], eta)) * (1.0 - dielectric_fresnel(wo[:, 2], eta))
        out = inner(wi, wo) * t[:, None]
        out[(wi[:, 2] <= 0) | (wo[:, 2] <= 0)] = 0.0
        return out

    return f


def dielectric_fresnel(cos_outside: np.ndarray, eta: float = CLEAR_COAT_ETA) -> np.ndarray:
    """Unpolarised Fresnel reflectance of light arriving from outside (index 1) onto index eta."""
    ci = np.clip(np.asarray(cos_outside, dtype=np.float64), 0.0, 1.0)
    ct = np.sqrt(np.maximum(1.0 - (1.0 - ci * ci) / (eta * eta), 0.0))
    rs = (ci - eta * ct) / np.maximum(ci + eta * ct, 1e-300)
    rp = (eta * ci - ct) / np.maximum(eta * ci + ct, 1e-300)
    return 0.5 * (rs * rs + rp * rp)
