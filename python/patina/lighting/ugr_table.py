"""The UGR table of a luminaire by the tabular method (CIE 117:1995, CIE 190:2010): the CIE 117
formula evaluated in standard rooms filled with a regular array of the luminaire.

A standard room is X by Y (multiples of H, the luminaires' height above the eye), the observer
seated at the middle of a wall of length X, eye 1.2 m above the floor, looking horizontally
along Y. The luminaires hang from the ceiling H above the eye on a square grid of spacing S
(S = 1.0 H for CIE 190's standard-condition table, 0.25 H for CIE 117's original one), the
first row S / 2 from the walls. "Crosswise": the line of sight at right angles to the
luminaire's C0-C180 plane's normal, i.e. along C0 (the lamp axis, C90-C270, across the view);
"endwise": the line of sight along C90 (along the lamp axis).

UGR = 8 log10(0.25 / L_b x sum L^2 omega / p^2) over the luminaires ahead of the eye (the
position index is defined there), L = I / A_p and omega = A_p / r^2 with A_p the flat luminous
opening seen at the angle gamma from nadir, p Guth's position index (patina.lighting.indoor).

L_b = E_ind / pi. E_ind, the interreflected illuminance at the eye, is reconstructed (CIE 190's
text is not public) as the walls' mean interreflected illuminance in a three-surface radiosity
of the room between the eye plane and the ceiling: the luminaires' direct flux onto the eye
plane (floor reflectance), the walls and the ceiling from the candela table, the surfaces'
exchange by the exact form factor of two parallel rectangles and the sum rule. Everything scales
with the candela table: a table k times brighter gives UGR + 8 log10 k, so a lamp flux other than
the file's adds 8 log10(flux / file flux) (`correction_db`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from patina.errors import FormatError
from patina.lighting.indoor import position_index
from patina.photometry.luminaire import Luminaire

EYE_HEIGHT = 1.2  # m, a seated observer (CIE 117)
H = 2.0  # m; the table does not depend on it (every length scales with H), the ceiling is at 3.2 m
# CIE 190's standard rooms (X, Y in H) and reflectance triples (ceiling, walls, floor)
ROOMS = [(2, y) for y in (2, 3, 4, 6, 8, 12)] + [(4, y) for y in (2, 3, 4, 6, 8, 12)]
ROOMS += [(8, y) for y in (4, 6, 8, 12)] + [(12, y) for y in (4, 6, 8)]
REFLECTANCES = [(0.7, 0.5, 0.2), (0.7, 0.3, 0.2), (0.5, 0.5, 0.2), (0.5, 0.3, 0.2), (0.3, 0.3, 0.2)]
VIEWS = ("crosswise", "endwise")
GAMMA_STEP, C_STEP = 1.0, 5.0  # degrees: the direction grid integrating each luminaire's flux


def luminous_area(lum: Luminaire) -> float:
    """The flat luminous opening in m^2 (rectangle, or the ellipse inside width x length); 0 when
    the file declares none."""
    o = lum.photometry.opening
    area = abs(o.width * o.length)
    return area if o.shape in ("rectangle", "box") else math.pi * area / 4


def parallel_rectangles(a: float, b: float, c: float) -> float:
    """Form factor between two equal, directly opposed parallel a x b rectangles c apart."""
    x, y = a / c, b / c
    qx, qy = math.sqrt(1 + x * x), math.sqrt(1 + y * y)
    return (
        2
        / (math.pi * x * y)
        * (
            math.log(qx * qy / math.sqrt(1 + x * x + y * y))
            + x * qy * math.atan(x / qy)
            + y * qx * math.atan(y / qx)
            - x * math.atan(x)
            - y * math.atan(y)
        )
    )


def _positions(x_h: float, y_h: float, spacing_h: float) -> np.ndarray:
    """Luminaire centres (n, 2) in metres, the eye at (X / 2, 0): x across, y along the sight."""
    s = spacing_h * H
    xs = np.arange(s / 2, x_h * H, s)
    ys = np.arange(s / 2, y_h * H, s)
    gx, gy = np.meshgrid(xs, ys, indexing="ij")
    return np.stack([gx.ravel(), gy.ravel()], axis=1)


def _direct_flux(lum: Luminaire, x_h: float, y_h: float, pos: np.ndarray, c0_along_y: bool) -> np.ndarray:
    """Lumens reaching (eye plane, walls, ceiling) directly from every luminaire of the room."""
    gamma = np.radians(np.arange(GAMMA_STEP / 2, 180, GAMMA_STEP))
    c = np.radians(np.arange(C_STEP / 2, 360, C_STEP))
    g, cc = np.meshgrid(gamma, c, indexing="ij")
    omega = np.radians(GAMMA_STEP) * np.radians(C_STEP) * np.sin(g)
    flux = (lum.intensity(g, cc).astype(np.float64) * omega).ravel()
    down = (g < math.pi / 2).ravel()
    # the horizontal direction of each C angle in room coordinates (x across, y along the sight)
    dx, dy = (np.sin(cc), np.cos(cc)) if c0_along_y else (np.cos(cc), np.sin(cc))
    reach = (H * np.tan(np.minimum(g, math.radians(89.999)))).ravel()
    floor = 0.0
    for px, py in pos:  # a numpy sum over directions per luminaire
        hx, hy = px + reach * dx.ravel(), py + reach * dy.ravel()
        inside = down & (hx >= 0) & (hx <= x_h * H) & (hy >= 0) & (hy <= y_h * H)
        floor += flux[inside].sum()
    upward = flux[~down].sum() * len(pos)
    walls = flux[down].sum() * len(pos) - floor
    return np.array([floor, walls, upward])


def _indirect_on_walls(direct: np.ndarray, x_h: float, y_h: float, rho: tuple[float, float, float]) -> float:
    """The walls' mean interreflected illuminance (lx) of the box eye plane / walls / ceiling."""
    a, b = x_h * H, y_h * H
    area = np.array([a * b, 2 * (a + b) * H, a * b])  # eye plane, walls, ceiling
    f_fc = parallel_rectangles(a, b, H)
    f_wf = area[0] * (1 - f_fc) / area[1]
    f = np.array([[0.0, 1 - f_fc, f_fc], [f_wf, 1 - 2 * f_wf, f_wf], [f_fc, 1 - f_fc, 0.0]])
    r = np.array([rho[2], rho[1], rho[0]])
    e_direct = direct / area
    # M = r (E_direct + F M): the exitances; the interreflected illuminance is F M
    m = np.linalg.solve(np.eye(3) - r[:, None] * f, r * e_direct)
    return float((f @ m)[1])


def _glare_sum(lum: Luminaire, area: float, x_h: float, pos: np.ndarray, c0_along_y: bool) -> float:
    dx, dy = pos[:, 0] - x_h * H / 2, pos[:, 1]
    r = np.sqrt(dx * dx + dy * dy + H * H)
    # from the luminaire towards the eye: gamma from nadir, C from C0 in the luminaire's frame
    gamma = np.arccos(H / r)
    c = np.arctan2(-dx, -dy) if c0_along_y else np.arctan2(-dy, -dx)
    candela = lum.intensity(gamma, c).astype(np.float64)
    projected = area * H / r
    luminance = np.divide(candela, projected, out=np.zeros_like(candela), where=projected > 0)
    sigma = np.degrees(np.arccos(dy / r))
    tau = np.degrees(np.arctan2(np.abs(dx), H))
    return float((luminance**2 * projected / r**2 / position_index(sigma, tau) ** 2).sum())


@dataclass(frozen=True)
class UgrTable:
    """UGR per (room, reflectances, view); `flux` the lamp lumens the table is for."""

    source: str
    spacing_h: float
    flux: float
    area: float
    values: dict[tuple[int, int, tuple[float, float, float], str], float]

    def correction_db(self, flux: float) -> float:
        """What to add to the table's values for lamps of `flux` lumens instead."""
        return 8 * math.log10(flux / self.flux)

    def rows(self) -> list[tuple[str, list[float], list[float]]]:
        """(room "XH x YH", crosswise values, endwise values) per standard room, the values in
        REFLECTANCES' order: the layout the catalogues print."""
        return [
            (
                f"{x_h}H x {y_h}H",
                *([self.values[(x_h, y_h, rho, view)] for rho in REFLECTANCES] for view in VIEWS),
            )
            for x_h, y_h in ROOMS
        ]

    def caption(self) -> str:
        return (
            f"S = {self.spacing_h:g} H, eye at {EYE_HEIGHT} m, lamp flux {self.flux:.0f} lm, "
            f"luminous area {self.area * 1e4:.0f} cm²; for a lamp flux F add 8 log10(F / {self.flux:.0f} lm)"
        )

    def to_json(self) -> dict:
        return {
            "source": self.source,
            "method": "CIE 117 formula over CIE 190's standard rooms (background reconstructed: docs/lighting.md)",
            "spacing_to_height": self.spacing_h,
            "eye_height_m": EYE_HEIGHT,
            "lamp_flux_lm": self.flux,
            "luminous_area_m2": self.area,
            "rows": [
                {"X_H": x, "Y_H": y, "ceiling": c, "walls": w, "floor": f, "view": view, "ugr": round(v, 2)}
                for (x, y, (c, w, f), view), v in self.values.items()
            ],
        }


def ugr_table(lum: Luminaire, spacing_h: float = 1.0) -> UgrTable:
    """The luminaire's UGR table; refused when the file declares no luminous area or sends no
    light downwards (no glare to rate), naming the file."""
    if not 0 < spacing_h <= 2:
        raise FormatError("command line", "--spacing", f"expected a spacing to height in (0, 2], got {spacing_h:g}")
    where = lum.path
    if lum.kind != "C":
        raise FormatError(where, "photometric type", "UGR tables are for type C (indoor) photometry")
    area = luminous_area(lum)
    if area <= 0:
        raise FormatError(where, "luminous opening", "declares no luminous area (IES width x length): no UGR")
    declared = lum.photometry.lumens
    flux = float(declared) if declared else lum.flux()
    values = {}
    for x_h, y_h in ROOMS:
        pos = _positions(x_h, y_h, spacing_h)
        for view in VIEWS:
            along = view == "crosswise"
            glare = _glare_sum(lum, area, x_h, pos, along)
            direct = _direct_flux(lum, x_h, y_h, pos, along)
            for rho in REFLECTANCES:
                e_ind = _indirect_on_walls(direct, x_h, y_h, rho)
                if glare <= 0 or e_ind <= 0:
                    raise FormatError(where, "candela table", "sends no light towards the standard rooms' eye")
                values[(x_h, y_h, rho, view)] = 8 * math.log10(0.25 * math.pi / e_ind * glare)
    return UgrTable(where, spacing_h, flux, area, values)


def format_table(table: UgrTable) -> str:
    """The table as the catalogues print it: a row per room, the reflectance triples across,
    crosswise then endwise."""
    head = "  ".join(f"{c:.1f}/{w:.1f}/{f:.1f}" for c, w, f in REFLECTANCES)
    lines = [
        f"UGR table of {table.source} (CIE 117 formula, CIE 190 rooms)",
        table.caption(),
        f"ceiling/walls/floor   {'crosswise':^{len(head)}}  |  {'endwise':^{len(head)}}",
        f"room                  {head}  |  {head}",
    ]
    for room, crosswise, endwise in table.rows():
        cells = ["  ".join(f"{v:>11.1f}" for v in values) for values in (crosswise, endwise)]
        lines.append(f"{room:<22}{cells[0]}  |  {cells[1]}")
    return "\n".join(lines)
