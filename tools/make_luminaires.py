"""Writes the bundled luminaires in materials/luminaires/ from analytic intensity models.

    python tools/make_luminaires.py [--out materials/luminaires]

Each model is normalised so that its continuous distribution emits exactly the declared
lumens (midpoint quadrature on a 0.02 deg grid, float64); the files then hold the model
sampled at their angles. Reading a file back and integrating the interpolated table gives
the declared lumens up to the table's sampling error (tests/python/photometry/test_readers.py).

Every model is a function of the direction: at a pole of the angle grid (type C gamma 0 and
180, type B H = +-90) every plane gets the same value: the street light's C-dependent terms
carry sin(gamma), the floodlight varies vertically with the direction's elevation (0 at
H = +-90 whatever V), and every table written is checked for it (`pole_warnings`, the
readers' check, and the rounded values themselves).
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable

import numpy as np

# the installed package (make setup): patina/__init__ needs its compiled core
from patina.photometry.model import pole_warnings
from patina.photometry.writers import format_ies, format_ldt

SCRIPT = "tools/make_luminaires.py"


def downlight(c: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Round downlight: cos^3 of gamma with a reflector cut-off fading out from 50 to 60 deg."""
    g = np.radians(g)
    taper = np.clip((np.radians(60.0) - g) / np.radians(10.0), 0.0, 1.0)
    return np.cos(np.minimum(g, np.pi / 2)) ** 3 * taper + 0 * c


def street(c: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Street light on an arm along +X (the street side, C0); the road runs along C90-C270.
    A soft downward part plus two lobes at gamma 65 deg swung 60 deg from C0 along the road,
    stronger on the street side than the house side (C180); full cut-off at gamma 90.
    The C-dependent terms grow with sin(gamma) from nadir, where every C plane meets."""
    a = np.abs(np.mod(c + 180.0, 360.0) - 180.0)  # |C| folded to 0..180: symmetric about C0-C180
    s = np.sin(np.radians(g))
    lobe = np.exp(-(((g - 65.0) / 11.0) ** 2)) * np.exp(-(((a - 60.0) / 28.0) ** 2)) * s
    base = 0.35 * np.cos(np.radians(np.minimum(g, 90.0)))
    street_side = 1.0 + 0.5 * np.cos(np.radians(a)) * s  # 1 + 0.5 d_x: brighter towards +X
    cutoff = np.clip((90.0 - g) / 8.0, 0.0, 1.0)
    return (base + lobe) * street_side * cutoff


def flood(h: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Floodlight, type B: an elliptical beam 2 x 22 deg wide by 2 x 12 deg high, aimed 4 deg
    above the axis, with a faint wide spill. Vertically it varies with the elevation of the
    direction, e = asin(cos H sin V) (= V on the beam axis), which is 0 at the poles H = +-90
    whatever V: one value there."""
    e = np.degrees(np.arcsin(np.cos(np.radians(h)) * np.sin(np.radians(v))))
    core = np.exp(-((h / 22.0) ** 2) - (((e - 4.0) / 12.0) ** 2))
    spill = 0.04 * np.exp(-((h / 55.0) ** 2) - ((e / 40.0) ** 2))
    return core + spill


def continuous_flux(model: Callable[[np.ndarray, np.ndarray], np.ndarray], kind: str) -> float:
    """Flux of a unit-scale model by the midpoint rule on a 0.02 deg grid (error << 1e-5)."""
    step = 0.02
    if kind == "C":
        g = np.arange(step / 2, 180.0, step)
        c = np.arange(step / 2, 360.0, 1.0)  # the models vary slowly in C
        total = 0.0
        for ci in c:
            total += np.sum(model(np.full_like(g, ci), g) * np.sin(np.radians(g))) * np.radians(step)
        return total * np.radians(1.0)
    h = np.arange(-90.0 + step / 2, 90.0, step)
    v = np.arange(-90.0 + 0.25, 90.0, 0.5)
    total = 0.0
    for vi in v:
        total += np.sum(model(h, np.full_like(h, vi)) * np.cos(np.radians(h))) * np.radians(step)
    return total * np.radians(0.5)


def sample(model: Callable, h: np.ndarray, v: np.ndarray, scale: float) -> np.ndarray:
    hh, vv = np.meshgrid(h, v, indexing="ij")
    return model(hh, vv) * scale


def provenance(name: str, what: str, model: str, files: list[str], measured: str) -> str:
    return f"""# {name}

{what}

- Files: {", ".join(f"`{f}`" for f in files)}
- Made by `{SCRIPT}` (`python {SCRIPT}`), from the analytic model below; no measurement.
- Model: {model}
- {measured}
- Licence: CC0 1.0 (public domain dedication). Synthetic data, free for any use.
"""


def check_poles(name: str, kind: str, h: np.ndarray, v: np.ndarray, cd: np.ndarray) -> None:
    """The written table gives each pole one value (as the readers check)."""
    problems = pole_warnings(name, kind, h, v, cd, np.zeros(cd.shape, int))
    if problems or _pole_spread(kind, h, v, cd) > 0.0:
        raise SystemExit(f"{name}: the model gives a pole several values: {problems or 'rounding'}")


def _pole_spread(kind: str, h: np.ndarray, v: np.ndarray, cd: np.ndarray) -> float:
    """Largest spread of the values written (rounded as in the file) at one pole."""
    cd = np.round(cd, 2)
    at = [cd[:, j] for j in range(len(v)) if kind == "C" and v[j] in (0.0, 180.0)]
    at += [cd[i] for i in range(len(h)) if kind == "B" and h[i] in (-90.0, 90.0)]
    return max((float(x.max() - x.min()) for x in at), default=0.0)


def write(path: str, text: str) -> None:
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="ascii", newline="") as f:
        f.write(text)
    os.replace(tmp, path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "materials", "luminaires"))
    out = ap.parse_args().out
    os.makedirs(out, exist_ok=True)

    # round downlight: LM-63-2019, type C, one plane (rotationally symmetric)
    lumens = 1500.0
    g = np.arange(0.0, 90.0 + 1e-9, 2.5)
    scale = lumens / continuous_flux(downlight, "C")
    cd = sample(downlight, np.array([0.0]), g, scale)
    check_poles("downlight", "C", np.array([0.0]), g, cd)
    keywords = {
        "TEST": "PATINA-SYN-001",
        "TESTLAB": "none (synthetic)",
        "ISSUEDATE": "2025-01-01",
        "MANUFAC": "Patina (synthetic)",
        "LUMCAT": "PAT-DL-1500",
        "LUMINAIRE": "Round downlight, 150 mm opening, cos^3 with a 50-60 deg cut-off",
        "LAMP": "LED module 1500 lm",
        "OTHER": "Generated by tools/make_luminaires.py from an analytic model; CC0",
    }
    text = format_ies(
        [0.0],
        g,
        cd,
        version="LM-63-2019",
        keywords=keywords,
        lamps=1,
        lumens_per_lamp=lumens,
        opening_m=(-0.15, -0.15, 0.0),
        watts=14.0,
        second_factor=1.00001,
        fmt="{:.2f}",
    )
    write(os.path.join(out, "downlight.ies"), text)
    write(
        os.path.join(out, "downlight.md"),
        provenance(
            "Round downlight (IES LM-63-2019)",
            "A recessed round downlight: type C photometry, one C plane (rotationally symmetric), "
            "gamma 0-90 deg in 2.5 deg steps, 1500 lm (relative photometry: 1 lamp of 1500 lm, "
            "candela multiplier 1, the table is the whole luminaire's output).",
            f"I(gamma) = I0 cos^3(gamma) t(gamma), t falling linearly from 1 at 50 deg to 0 at 60 deg; "
            f"I0 = {scale:.2f} cd so the continuous distribution emits exactly 1500 lm.",
            ["downlight.ies"],
            "Opening: 150 mm disk (LM-63 negative width/length). Input watts 14 W.",
        ),
    )

    # street light: LM-63-2002 type C, 0-180 (symmetric about the C0-C180 plane), and the same as EULUMDAT Isym 2
    lumens = 12000.0
    g = np.arange(0.0, 90.0 + 1e-9, 2.5)
    c_half = np.arange(0.0, 180.0 + 1e-9, 5.0)
    scale = lumens / continuous_flux(street, "C")
    cd = sample(street, c_half, g, scale)
    check_poles("streetlight", "C", c_half, g, cd)
    keywords = {
        "TEST": "PATINA-SYN-002",
        "MANUFAC": "Patina (synthetic)",
        "LUMCAT": "PAT-ST-12K",
        "LUMINAIRE": "Street light, arm along C0 (street side), road along C90-C270",
        "LAMP": "LED module 12000 lm",
    }
    keywords["OTHER"] = "Generated by tools/make_luminaires.py from an analytic model\nCC0 1.0"
    text = format_ies(
        c_half,
        g,
        cd,
        version="LM-63-2002",
        keywords=keywords,
        lamps=1,
        lumens_per_lamp=lumens,
        opening_m=(0.3, 0.6, 0.0),
        watts=95.0,
        fmt="{:.2f}",
    )
    write(os.path.join(out, "streetlight.ies"), text)
    c_all = np.arange(0.0, 360.0 - 1e-9, 5.0)
    ldt = format_ldt(
        c_all,
        g,
        cd / (lumens / 1000.0),
        isym=2,
        lamp_flux=lumens,
        lorl=100.0,
        company="Patina (synthetic)",
        luminaire="Street light, arm along C0, road along C90-C270",
        number="PAT-ST-12K",
        report="PATINA-SYN-002",
        lamp_type="LED module 12000 lm",
        watts=95.0,
        size_mm=(600, 300, 80),
        area_mm=(600, 300),
        fmt="{:.4f}",
    )
    write(os.path.join(out, "streetlight.ldt"), ldt)
    write(
        os.path.join(out, "streetlight.md"),
        provenance(
            "Street light (IES LM-63-2002 and EULUMDAT)",
            "An asymmetric street light, the same table twice: `streetlight.ies` (type C, horizontal "
            "angles 0-180: symmetric about the C0-C180 plane) and `streetlight.ldt` (Isym 2, the same "
            "symmetry, intensities in cd/klm for one 12000 lm lamp set, LORL 100 %). The arm and the "
            "street side lie along C0 (luminaire +X), the road runs along C90-C270. Gamma 0-90 in "
            "2.5 deg steps, C planes every 5 deg; 12000 lm.",
            "I = k (0.35 cos(gamma) + L) (1 + 0.5 sin(gamma) cos C) f(gamma), L = exp(-((gamma - 65)/11)^2) "
            "exp(-((|C| - 60)/28)^2) sin(gamma) (angles in degrees), f falling linearly from 1 at 82 deg to 0 at "
            f"90 deg (full cut-off); k = {scale:.2f} cd so the continuous distribution emits 12000 lm. "
            "The C-dependent terms carry sin(gamma), so straight down (gamma 0, where every C plane meets) "
            "the intensity is one value, 0.35 k.",
            ["streetlight.ies", "streetlight.ldt"],
            "Luminous opening 600 x 300 mm; 95 W.",
        ),
    )

    # floodlight: LM-63-2002 type B, H 0..90 (laterally symmetric), V -90..90
    lumens = 20000.0
    h = np.arange(0.0, 90.0 + 1e-9, 2.5)
    v = np.arange(-90.0, 90.0 + 1e-9, 2.5)
    scale = lumens / continuous_flux(flood, "B")
    cd = sample(flood, h, v, scale)
    check_poles("floodlight", "B", h, v, cd)
    keywords = {
        "TEST": "PATINA-SYN-003",
        "MANUFAC": "Patina (synthetic)",
        "LUMCAT": "PAT-FL-20K",
        "LUMINAIRE": "Floodlight, elliptical beam",
        "LAMP": "LED module 20000 lm",
        "OTHER": "Generated by tools/make_luminaires.py from an analytic model; CC0",
    }
    text = format_ies(
        h,
        v,
        cd,
        version="LM-63-2002",
        keywords=keywords,
        lamps=1,
        lumens_per_lamp=lumens,
        photometric_type=2,
        opening_m=(0.4, 0.3, 0.0),
        watts=160.0,
        fmt="{:.2f}",
    )
    write(os.path.join(out, "floodlight.ies"), text)
    write(
        os.path.join(out, "floodlight.md"),
        provenance(
            "Floodlight (IES LM-63-2002, type B)",
            "A floodlight measured in type B photometry: horizontal angles 0-90 (laterally symmetric), "
            "vertical angles -90..90, both in 2.5 deg steps; 20000 lm. The beam axis is H = V = 0 "
            "(luminaire +Z, docs/luminaires.md).",
            "I = k (exp(-(H/22)^2 - ((e - 4)/12)^2) + 0.04 exp(-(H/55)^2 - (e/40)^2)) (degrees), "
            "e = asin(cos H sin V) the elevation of the direction (e = V on the beam axis, 0 at the poles "
            f"H = +-90 whatever V, so the poles get one value); k = {scale:.2f} cd so the continuous "
            "distribution emits 20000 lm.",
            ["floodlight.ies"],
            "Opening 400 x 300 mm; 160 W.",
        ),
    )
    print(f"wrote downlight, streetlight (.ies, .ldt), floodlight to {os.path.abspath(out)}")


if __name__ == "__main__":
    main()
