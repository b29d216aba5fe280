"""Writers for IES LM-63 and EULUMDAT text, for the bundled luminaires
(tools/make_luminaires.py) and for tests; the readers are the reference for what they accept."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def _wrap(values: Sequence[float], fmt: str, per_line: int = 10) -> list[str]:
    vals = [fmt.format(v) for v in values]
    return [" ".join(vals[i : i + per_line]) for i in range(0, len(vals), per_line)] or [""]


def format_ies(
    h_deg: Sequence[float],
    v_deg: Sequence[float],
    candela: np.ndarray,
    *,
    version: str = "LM-63-2002",
    keywords: dict[str, str] | None = None,
    lamps: int = 1,
    lumens_per_lamp: float = -1,
    multiplier: float = 1.0,
    photometric_type: int = 1,
    opening_m: tuple[float, float, float] = (0.0, 0.0, 0.0),
    ballast: float = 1.0,
    second_factor: float = 1.0,
    watts: float = 0.0,
    tilt: str = "NONE",
    tilt_block: tuple[int, Sequence[float], Sequence[float]] | None = None,
    fmt: str = "{:.6g}",
) -> str:
    """IES text; candela (len(h), len(v)). `version` "LM-63-1986" writes no version line,
    "LM-63-2019" writes `IES:LM-63-2019`, others `IESNA:LM-63-yyyy`."""
    candela = np.asarray(candela, np.float64)
    out: list[str] = []
    if version == "LM-63-2019":
        out.append("IES:LM-63-2019")
    elif version == "LM-63-1991":
        out.append("IESNA91")
    elif version != "LM-63-1986":
        out.append(f"IESNA:{version}")
    for key, value in (keywords or {}).items():
        first, *more = value.split("\n")
        out.append(f"[{key}] {first}")
        out.extend(f"[MORE] {m}" for m in more)
    out.append(f"TILT={tilt}")
    if tilt_block is not None:
        geometry, angles, factors = tilt_block
        out += [str(geometry), str(len(angles)), *_wrap(angles, "{:g}"), *_wrap(factors, "{:g}")]
    w, ln, ht = opening_m
    out.append(
        f"{lamps} {lumens_per_lamp:g} {multiplier:g} {len(v_deg)} {len(h_deg)} {photometric_type} 2 {w:g} {ln:g} {ht:g}"
    )
    out.append(f"{ballast:g} {second_factor:g} {watts:g}")
    out += _wrap(v_deg, "{:g}")
    out += _wrap(h_deg, "{:g}")
    for row in candela:
        out += _wrap(row, fmt)
    return "\r\n".join(out) + "\r\n"


def format_ldt(
    c_deg: Sequence[float],
    g_deg: Sequence[float],
    cd_per_klm: np.ndarray,
    *,
    isym: int,
    lamp_flux: float,
    lamps: int = 1,
    lorl: float = 100.0,
    company: str = "Patina",
    luminaire: str = "",
    number: str = "",
    report: str = "",
    lamp_type: str = "LED",
    watts: float = 0.0,
    size_mm: tuple[float, float, float] = (0.0, 0.0, 0.0),
    area_mm: tuple[float, float] = (0.0, 0.0),
    dff: float = 100.0,
    fmt: str = "{:.6g}",
) -> str:
    """EULUMDAT text: all Mc C angles `c_deg` (0 up to below 360), gamma angles, and the
    stored planes' intensities in cd/klm (rows in file order, as Isym selects them)."""
    cd = np.asarray(cd_per_klm, np.float64)
    mc, ng = len(c_deg), len(g_deg)
    dc = c_deg[1] - c_deg[0] if mc > 1 and np.allclose(np.diff(c_deg), c_deg[1] - c_deg[0]) else 0
    dg = g_deg[1] - g_deg[0] if ng > 1 and np.allclose(np.diff(g_deg), g_deg[1] - g_deg[0]) else 0
    ityp = 1 if isym == 1 else 3
    out = [company, str(ityp), str(isym), str(mc), f"{dc:g}", str(ng), f"{dg:g}", report, luminaire, number]
    out += ["", "", *(f"{x:g}" for x in size_mm), *(f"{x:g}" for x in area_mm), "0", "0", "0", "0"]
    out += [f"{dff:g}", f"{lorl:g}", "1", "0", "1"]
    out += [str(lamps), lamp_type, f"{lamp_flux:g}", "4000", "80", f"{watts:g}"]
    out += ["0"] * 10
    out += [f"{c:g}" for c in c_deg]
    out += [f"{g:g}" for g in g_deg]
    out += [fmt.format(x) for x in cd.ravel()]
    return "\r\n".join(out) + "\r\n"
