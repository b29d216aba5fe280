"""Mitsuba 3: an AnalyticMaterial as a BSDF dictionary (`mi.load_dict`) and as scene XML.

Mitsuba has no BSDF that adds two others, only `blendbsdf`, a convex mix w a + (1 - w) b; a
sum of lobes is a tree of blends whose leaves carry their share's inverse in a linear
parameter (a `diffuse` reflectance, a `roughconductor`'s specular_reflectance). A GGX lobe
with Schlick Fresnel, f0 + (1 - f0) m G (G the lobe at F = 1, m = (1 - cos_d)^5), is written
exactly: Mitsuba's `principled` at metallic 1 is Schlick of its base colour b times G, with
no linear parameter, so it enters a blend at the weight w = 1 - min(f0) with
b = 1 - (1 - f0) / w, and the rest, min(f0) G, is a `roughconductor` of material `none`
(Fresnel 1). Under a coat the lobe is scaled by the coat's normal-incidence transmission
(approximate: Patina's is per direction). Where that cannot be (Beckmann lobes, fixed
weights adding to 1 or more) a lobe is a `roughconductor` whose conductor Fresnel (eta, k) and
specular_reflectance are fitted to the Schlick curve: approximate, the notes say so. A
Lambert base under a coat is `roughplastic` (`plastic` for a coat with alpha <= 0.005;
nonlinear off) with its diffuse reflectance multiplied by (1 - Fdr_int) eta^2, which undoes
Mitsuba's internal-reflection factor so that the base is rho / pi times the coat's
transmission in and out, as in Patina (roughplastic's transmission is its own average over
the rough coat's facets, not Patina's smooth one: a few percent apart). Mitsuba's Smith
term is separable (G1 G1), Patina's height-correlated: they differ at grazing angles.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from typing import Any

import numpy as np

from patina.export.material import AnalyticMaterial, Lobe

MITSUBA_VERSION = "3.5.0"
# a coat this smooth (the fit's lower bound on alpha) is Mitsuba's smooth `plastic`, whose
# diffuse part has the exact Fresnel transmission (roughplastic's is its own rough average)
SMOOTH_COAT_ALPHA = 0.005


def _rgb(value: Any) -> dict[str, Any]:
    """A constant colour; above 1 (a blend's leaf carrying its share's inverse) as Mitsuba's
    `srgb` texture with `unbounded`, which Mitsuba otherwise refuses for a reflectance."""
    rgb = [float(x) for x in value]
    if max(rgb) > 1:
        return {"type": "srgb", "color": rgb, "unbounded": True}
    return {"type": "rgb", "value": rgb}


def _fresnel_dielectric(cos_i: np.ndarray, eta: float) -> np.ndarray:
    sin2_t = (1 - cos_i**2) / eta**2
    cos_t = np.sqrt(np.maximum(1 - sin2_t, 0))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return np.where(sin2_t >= 1, 1.0, 0.5 * (rs * rs + rp * rp))


def internal_diffuse_reflectance(eta: float) -> float:
    """Fdr of light inside a medium of index eta meeting its boundary: 2 int F(cos, 1/eta) cos dcos
    (Mitsuba fits the same integral: they agree to its stated 0.1-0.6 %)."""
    c = (np.arange(4096) + 0.5) / 4096
    return float(2 * np.mean(_fresnel_dielectric(c, 1.0 / eta) * c))


def _fresnel_conductor(c: np.ndarray, n: float, k: float) -> np.ndarray:
    c2 = c * c
    s2 = 1 - c2
    t0 = n * n - k * k - s2
    a2b2 = np.sqrt(t0 * t0 + 4 * n * n * k * k)
    t1 = a2b2 + c2
    a = np.sqrt(np.maximum(0.5 * (a2b2 + t0), 0))
    t2 = 2 * c * a
    rs = (t1 - t2) / (t1 + t2)
    t3 = c2 * a2b2 + s2 * s2
    t4 = t2 * s2
    return 0.5 * (rs + rs * (t3 - t4) / (t3 + t4))


def conductor_for_schlick(f0: float) -> tuple[float, float, float]:
    """(eta, k, scale) whose scale x conductor Fresnel is closest to Schlick's curve of f0
    (relative least squares over cos_d in [0.05, 1])."""
    from scipy.optimize import least_squares

    f0 = min(max(f0, 1e-4), 0.999)
    c = np.linspace(0.05, 1.0, 96)
    schlick = f0 + (1 - f0) * (1 - c) ** 5
    start = [(1 + math.sqrt(f0)) / (1 - math.sqrt(f0)), 0.1, 1.0] if f0 < 0.2 else [0.5, 2.0, 1.0]
    r = least_squares(
        lambda p: p[2] * _fresnel_conductor(c, p[0], p[1]) / schlick - 1,
        start,
        bounds=([0.01, 0.0, 0.0], [10.0, 20.0, 10.0]),
    )
    return float(r.x[0]), float(r.x[1]), float(r.x[2])


def _approximate_lobe(lobe: Lobe, scale: float) -> dict[str, Any]:
    fits = [conductor_for_schlick(f) for f in lobe.f0]
    return {
        "type": "roughconductor",
        "distribution": lobe.distribution,
        "alpha": float(lobe.alpha),
        "eta": _rgb([f[0] for f in fits]),
        "k": _rgb([f[1] for f in fits]),
        "specular_reflectance": _rgb([f[2] * scale for f in fits]),
    }


def _blend(parts: list[tuple[float, dict[str, Any]]]) -> dict[str, Any]:
    """Nested blendbsdfs giving sum(weight_i part_i) for weights adding to 1."""
    if len(parts) == 1:
        return parts[0][1]
    (w, first), rest = parts[0], parts[1:]
    remainder = sum(p[0] for p in rest)
    inner = _blend([(p[0] / remainder, p[1]) for p in rest])
    return {"type": "blendbsdf", "weight": float(remainder / (w + remainder)), "bsdf_0": first, "bsdf_1": inner}


def to_mitsuba_dict(material: AnalyticMaterial, notes: list[str] | None = None) -> dict[str, Any]:
    """The material as a Mitsuba 3 BSDF dictionary for `mi.load_dict`; `notes` (a list) gets
    what is approximate."""
    notes = notes if notes is not None else []
    has_diffuse = material.coat is not None or any(r > 0 for r in material.diffuse)
    fixed_weight = sum(_under_coat(material) * (1 - min(lobe.f0)) for lobe in material.lobes)
    # the exact form needs room beside the principled lobes' fixed weights for the scaled parts
    exact = all(lobe.distribution == "ggx" for lobe in material.lobes) and (
        fixed_weight < 0.999 or (fixed_weight <= 1 and not has_diffuse and len(material.lobes) == 1)
    )
    return _to_dict(material, notes, exact)


def _under_coat(material: AnalyticMaterial) -> float:
    """What the lobes under a coat are multiplied by: the coat's transmission in and out at
    normal incidence, (1 - F0)^2, standing for Patina's (1 - F(cos_i)) (1 - F(cos_o)), which
    no Mitsuba BSDF applies to a lobe."""
    if material.coat is None:
        return 1.0
    eta = material.coat.eta
    return (1 - ((eta - 1) / (eta + 1)) ** 2) ** 2


def _to_dict(material: AnalyticMaterial, notes: list[str], exact_ggx: bool) -> dict[str, Any]:
    # unscaled: (weight, bsdf) with the weight fixed; scaled: (coefficient, maker(scale) -> bsdf)
    fixed: list[tuple[float, dict[str, Any]]] = []
    scaled: list[tuple[float, Any]] = []
    coat = material.coat
    rho = material.diffuse
    if coat:
        fdr = internal_diffuse_reflectance(coat.eta)

        def plastic(s: float) -> dict[str, Any]:
            out = {
                "type": "plastic",
                "int_ior": float(coat.eta),
                "ext_ior": 1.0,
                "nonlinear": False,
                "diffuse_reflectance": _rgb([r * (1 - fdr) * coat.eta**2 * s for r in rho]),
                "specular_reflectance": _rgb([s] * 3),
            }
            if coat.alpha > SMOOTH_COAT_ALPHA:
                out.update(type="roughplastic", distribution="ggx", alpha=float(coat.alpha))
            return out

        scaled.append((1.0, plastic))
    elif any(r > 0 for r in rho):
        scaled.append((1.0, lambda s: {"type": "diffuse", "reflectance": _rgb([r * s for r in rho])}))
    t0 = _under_coat(material)
    for lobe in material.lobes:
        if exact_ggx:
            # t0 (f0 + (1 - f0) m) G = w (b + (1 - b) m) G + t0 min(f0) G with w = t0 (1 - min f0)
            w = t0 * (1 - min(lobe.f0))
            roughness = math.sqrt(lobe.alpha)
            if w > 0:
                base = [1 - (1 - f) / (1 - min(lobe.f0)) for f in lobe.f0]
                fixed.append(
                    (
                        w,
                        {
                            "type": "principled",
                            "base_color": _rgb(base),
                            "metallic": 1.0,
                            "roughness": roughness,
                            "specular": 0.5,
                        },
                    )
                )
            if min(lobe.f0) > 0:
                alpha = float(lobe.alpha)
                scaled.append(
                    (
                        t0 * min(lobe.f0),
                        lambda s, a=alpha: {
                            "type": "roughconductor",
                            "material": "none",
                            "distribution": "ggx",
                            "alpha": a,
                            "specular_reflectance": _rgb([s] * 3),
                        },
                    )
                )
        else:
            scaled.append((t0, lambda s, lb=lobe: _approximate_lobe(lb, s)))
            note = f"{lobe.distribution} lobe: Schlick Fresnel approximated by a fitted conductor Fresnel"
            if note not in notes:
                notes.append(note)
    if coat and material.lobes:
        notes.append("lobes under the coat: dimmed by its normal-incidence transmission (1 - F0)^2, not per direction")
    fixed_total = sum(w for w, _ in fixed)
    parts = list(fixed)
    if scaled and fixed_total < 1:
        share = (1 - fixed_total) / len(scaled)
        parts += [(share, make(coefficient / share)) for coefficient, make in scaled]
    if not parts:
        parts = [(1.0, {"type": "diffuse", "reflectance": _rgb([0, 0, 0])})]
    out = _blend(parts)
    if material.two_sided:
        out = {"type": "twosided", "bsdf": out}
    return out


def _xml_node(parent: ET.Element, name: str | None, value: Any) -> None:
    if isinstance(value, dict) and value.get("type") == "rgb":
        ET.SubElement(parent, "rgb", name=name, value=", ".join(f"{x:.9g}" for x in value["value"]))
    elif isinstance(value, dict) and value.get("type") == "srgb":
        node = ET.SubElement(parent, "texture", type="srgb", name=name)
        ET.SubElement(node, "rgb", name="color", value=", ".join(f"{x:.9g}" for x in value["color"]))
        ET.SubElement(node, "boolean", name="unbounded", value="true")
    elif isinstance(value, dict):
        node = ET.SubElement(parent, "bsdf", type=value["type"])
        if name and not name.startswith("bsdf"):
            node.set("name", name)
        for key, child in value.items():
            if key != "type":
                _xml_node(node, key, child)
    elif isinstance(value, bool):
        ET.SubElement(parent, "boolean", name=name, value="true" if value else "false")
    elif isinstance(value, (int, float)):
        ET.SubElement(parent, "float", name=name, value=f"{float(value):.9g}")
    else:
        ET.SubElement(parent, "string", name=name, value=str(value))


def to_mitsuba_xml(material: AnalyticMaterial, notes: list[str] | None = None) -> str:
    """A Mitsuba 3 scene file holding the material as a BSDF with id = the material's name
    (`<ref id="..."/>` it from a scene, or `mi.load_file` it alone)."""
    scene = ET.Element("scene", version=MITSUBA_VERSION)
    bsdf = to_mitsuba_dict(material, notes)
    _xml_node(scene, None, bsdf)
    scene[0].set("id", material.name)
    ET.indent(scene)
    comment = f"<!-- {material.name}: exported by patina export from {material.source} ({material.model}) -->\n"
    return comment + ET.tostring(scene, encoding="unicode") + "\n"


def mitsuba_eval(bsdf: Any, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
    """Mitsuba 3's own evaluation (scalar_rgb) of a BSDF (a dictionary, or one loaded) at (n, 3) local direction
    pairs, as a BRDF: Mitsuba's `eval` carries cos(theta_o), divided out here (its sign too,
    on the back side). Needs the `mitsuba` package (the `test` extra)."""
    import mitsuba as mi

    if mi.variant() != "scalar_rgb":
        mi.set_variant("scalar_rgb")
    if isinstance(bsdf, dict):
        bsdf = mi.load_dict(bsdf)
    ctx = mi.BSDFContext()
    si = mi.SurfaceInteraction3f()
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    out = np.zeros((len(wi), 3))
    for j in range(len(wi)):
        si.wi = mi.Vector3f(*wi[j])
        out[j] = np.array(bsdf.eval(ctx, si, mi.Vector3f(*wo[j]))) / wo[j, 2]
    return out
