"""Scene materials as the C++ renderer takes them (`RenderScene.add_material` dictionaries).

Each dictionary holds exactly the keys the renderer reads for its kind, every one of them
(the bindings reject a missing or an unread key, naming it): render/materials/, a type per kind.

Tables and fitted models are evaluated by the renderer as they are; what this module adds
is what the renderer needs *about* them: an albedo for the albedo AOV and the coat's lobe
choice, and a sampling proxy (a Lambert lobe with probability `proxy_diffuse`, else GGX
of roughness `proxy_alpha`) fitted to the BRDF's shape in a few hundred evaluations. The
proxy only steers importance sampling; values always come from the table, so a poor proxy
costs noise, never bias. An RGL file samples itself by its own warps; of the proxy it keeps
the roughness (`lobe_alpha`), by which the radiance cache decides as for a table.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from patina.colour_constants import luminance
from patina.errors import FormatError
from patina.fitting import read_fit
from patina.scene.reading import MAX_BRDF, OVERFLOWS
from patina.scene.types import (
    CarpaintMaterial,
    ConductorMaterial,
    DielectricMaterial,
    FitMaterial,
    LambertMaterial,
    Material,
    RglMaterial,
    TableMaterial,
)
from patina.table import angles_to_directions, load_brdf
from patina.table.formats.rgl_brdf import read_rgl_brdf
from patina.table.formats.rgl_native import native_rgl
from patina.table.spectral import as_linear_srgb

Eval = Callable[[np.ndarray, np.ndarray], np.ndarray]


def directional_albedo(evaluate: Eval, theta_deg: float = 30.0, n: int = 48) -> np.ndarray:
    """RGB albedo for light from theta_deg: the midpoint rule over (cos^2 theta, phi)."""
    c2 = (np.arange(n) + 0.5) / n  # cos^2 theta_o, uniform: dA = d(cos^2)/2 dphi absorbs cos
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    theta = np.arccos(np.sqrt(c2))
    tt, pp = np.meshgrid(theta, phi, indexing="ij")
    wo = angles_to_directions(tt.ravel(), pp.ravel())
    wi = np.broadcast_to(angles_to_directions(math.radians(theta_deg), 0.0), wo.shape)
    f = evaluate(np.ascontiguousarray(wi, np.float32), np.ascontiguousarray(wo, np.float32))
    # integral f cos dw = integral f d(cos^2)/2 dphi = mean(f) * pi
    return np.asarray(f, np.float64).mean(axis=0)[:3] * math.pi


def sampling_proxy(evaluate: Eval, theta_deg: float = 30.0) -> tuple[float, float]:
    """(proxy_diffuse, proxy_alpha): the diffuse share of the albedo, and the GGX roughness
    whose peak has the BRDF's half width at half maximum around the mirror direction."""
    tilt = np.radians(np.linspace(0.0, 45.0, 181))  # half-vector tilt from the mirror, in plane
    ti = math.radians(theta_deg)
    wi = angles_to_directions(ti, 0.0)
    h = np.stack([np.sin(-tilt), np.zeros_like(tilt), np.cos(tilt)], axis=1)
    wo = 2 * (h @ wi)[:, None] * h - wi
    ok = wo[:, 2] > 0.05
    f = np.asarray(
        evaluate(np.ascontiguousarray(np.broadcast_to(wi, wo.shape), np.float32), np.ascontiguousarray(wo, np.float32)),
        np.float64,
    )[:, :3]
    lum = np.where(ok, luminance(f), np.nan)
    floor = float(np.nanmin(lum)) if np.isfinite(lum).any() else 0.0
    spec = lum - floor
    albedo = float(luminance(directional_albedo(evaluate, theta_deg)))
    diffuse = min(0.9, max(0.1, math.pi * max(floor, 0.0) / albedo)) if albedo > 0 else 0.5
    if not np.isfinite(spec[0]) or spec[0] <= 0.05 * max(floor, 1e-12):
        return 0.9, 0.5  # no specular peak worth aiming at
    below = np.nonzero(~(spec > 0.5 * spec[0]))[0]
    half = float(tilt[below[0]]) if below.size else float(tilt[-1])
    # GGX: D(theta_h) / D(0) = 1/2 at theta_h ~ 0.6436 alpha; sample a little wider than the peak
    alpha = min(1.0, max(0.005, 1.2 * half / 0.6436))
    return diffuse, alpha


def _rgb(v: Any) -> list[float]:
    return [float(x) for x in v]


def _scaled(tint: Any, scale: float) -> list[float]:
    return [float(t) * scale for t in tint]


def _conductor_f0(eta: Any, k: Any) -> list[float]:
    return [((n - 1) ** 2 + kk**2) / ((n + 1) ** 2 + kk**2) for n, kk in zip(eta, k)]


def core_material(m: Material, tables: dict[str, Any]) -> dict[str, Any]:
    """A scene material as a `RenderScene.add_material` dictionary. `tables` caches loaded
    tables and fits by file (the dictionaries hold the core objects the renderer reads)."""
    if isinstance(m, LambertMaterial):
        return {"kind": "lambert", "albedo": _rgb(m.albedo), "two_sided": m.two_sided, "coat": False}
    if isinstance(m, ConductorMaterial):
        f0 = _conductor_f0(m.eta, m.k)
        return {  # roughness 0 (a mirror) becomes the renderer's narrowest lobe
            "kind": "conductor",
            "alpha_x": float(m.roughness[0]),
            "alpha_y": float(m.roughness[1]),
            "eta": _rgb(m.eta),
            "k": _rgb(m.k),
            "tint": _rgb(m.tint),
            "albedo": [a * t for a, t in zip(f0, m.tint)],
            "two_sided": m.two_sided,
            "coat": False,
        }
    if isinstance(m, TableMaterial | RglMaterial | FitMaterial):
        return _measured(m, tables)
    if isinstance(m, CarpaintMaterial):
        base = core_material(m.base, tables)
        base.update(
            coat=True,
            coat_eta=float(m.coat.eta),
            coat_alpha=float(m.coat.roughness),
            coat_tint=_rgb(m.coat.thickness_tint),
            two_sided=m.two_sided,
        )
        return base
    if isinstance(m, DielectricMaterial):
        # eta is inside over outside, the outside being where the triangles' winding normal points;
        # the renderer reads alpha_x and eta[0] (an isotropic, grey glass)
        return {"kind": "dielectric", "alpha_x": float(m.roughness), "eta": [float(m.eta)] * 3, "albedo": [1.0] * 3}
    raise ValueError(f"unknown material {type(m).__name__}")


def _read_measured(m: TableMaterial | RglMaterial | FitMaterial) -> tuple[dict[str, Any], Eval, float]:
    """The renderer's entry for the file (its kind and the core object), its evaluation, and
    the largest value it holds (0 where it is only known by evaluating)."""
    if isinstance(m, TableMaterial):
        brdf = as_linear_srgb(load_brdf(m.file))
        with np.errstate(all="ignore"):
            peak = float(np.nanmax(np.abs(brdf.values), initial=0.0))
        return {"kind": "table", "table": brdf.table}, brdf.eval, peak
    if isinstance(m, RglMaterial):
        native = native_rgl(read_rgl_brdf(m.file))

        def evaluate(wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
            return native.eval(wi, wo, width=0, threads=1)

        return {"kind": "rgl", "rgl": native}, evaluate, 0.0
    fitted = read_fit(m.file)
    mixture = (fitted.space.kernel_name, [float(v) for v in fitted.values], fitted.space.per_channel)
    return {"kind": "mixture", "mixture": mixture}, fitted.eval, 0.0


def _measured(m: TableMaterial | RglMaterial | FitMaterial, tables: dict[str, Any]) -> dict[str, Any]:
    key = f"{m.type}:{m.file}"  # a .bsdf may be both a table (resampled) and an RGL material
    if key not in tables:
        entry, evaluate, peak = _read_measured(m)
        with np.errstate(all="ignore"):  # a bad file is reported below, not by numpy warnings
            diffuse, alpha = sampling_proxy(evaluate)
            albedo = [float(a) for a in directional_albedo(evaluate)]
        if not all(math.isfinite(a) for a in albedo):
            raise FormatError(m.file, "values", f"its BRDF evaluates to values that are not finite: {OVERFLOWS}")
        if entry["kind"] == "rgl":  # its own warps sample it: the proxy's roughness is for the cache
            entry.update(lobe_alpha=alpha)
        else:
            entry.update(proxy_diffuse=diffuse, proxy_alpha=alpha)
        entry.update(albedo=albedo, peak=max(peak, *albedo))
        tables[key] = entry
    d = dict(tables[key])
    if isinstance(m, RglMaterial):
        d.update(sampling=m.sampling)
    tint = _scaled(m.tint, m.scale)
    # the renderer multiplies the values by tint (and by radiance) in 32-bit floats
    peak = d.pop("peak")
    if peak * max(tint) > MAX_BRDF:
        raise FormatError(
            m.file,
            "values",
            f"values up to {peak:g} times the material's scale and tint ({max(tint):g}) exceed {MAX_BRDF:g}: "
            f"{OVERFLOWS}",
        )
    d.update(tint=tint, albedo=[a * t for a, t in zip(d["albedo"], tint)], two_sided=m.two_sided, coat=False)
    return d
