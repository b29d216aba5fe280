"""The common photometric model both readers produce: `Photometry`, a candela table on the
full angular grid (symmetries already expanded), absolute candela with every multiplier
applied, and the file's declarations beside it. Conventions: docs/luminaires.md.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from patina.errors import FormatError

CUT_DEG = 0.01  # width of the drop to zero where a table stops short of the sphere (no light past its last angle)


@dataclass(frozen=True)
class Tilt:
    """Lamp output against luminaire tilt (IES TILT=INCLUDE or a TILT file): the factor
    multiplies every candela value when the luminaire is tilted by `angles_deg`.
    `geometry`: 1 vertical base-up or base-down lamp, 2 horizontal lamp along the 0-180 plane,
    3 horizontal lamp along the 90-270 plane (LM-63's lamp-to-luminaire geometry)."""

    geometry: int
    angles_deg: np.ndarray
    factors: np.ndarray


@dataclass(frozen=True)
class Opening:
    """The luminous opening in metres: `length` along the C0-C180 axis (luminaire +X),
    `width` along C90-C270 (+Y), `height` vertical. `shape` is "point", "rectangle",
    "box" (luminous sides), "disk", "ellipse", "sphere", "cylinder" or "other"."""

    width: float
    length: float
    height: float
    shape: str


@dataclass(frozen=True)
class Photometry:
    """One luminaire's photometry.

    type: "C" (h = C plane, v = gamma from nadir) or "B" (h = horizontal angle H, v = vertical
    angle V); `h_deg` ascending over the whole range (type C 0..360 inclusive, type B -90..90),
    `v_deg` ascending (type C 0..180, type B -180..180), angles past the file's own range
    hold zero candela. `candela[i, j]` at (h_deg[i], v_deg[j]), absolute, float32.
    `lumens`: the lamp lumens the file declares (all lamps; None for absolute photometry); the
    table's flux against them is the light output ratio.
    `luminaire_lumens`: the luminaire flux the file itself states, no multiplier applied:
    EULUMDAT lamp flux x LORL (or, for absolute photometry, its flux field); None for IES
    (LM-63 states no luminaire flux).
    `multiplier`: the product of the factors applied to the file's numbers.
    `warnings`: problems that do not stop the file being read, one line each naming the file,
    the place and the problem (e.g. one direction, a pole, given different values).
    """

    path: str
    format: str  # "IES" or "EULUMDAT"
    version: str
    type: str
    symmetry: str
    h_deg: np.ndarray
    v_deg: np.ndarray
    candela: np.ndarray
    file_h_deg: np.ndarray  # the angles as the file lists them
    file_v_deg: np.ndarray
    lumens: float | None
    luminaire_lumens: float | None
    lamps: int
    multiplier: float
    tilt: Tilt | None
    opening: Opening
    input_watts: float | None = None
    manufacturer: str = ""
    catalogue: str = ""
    luminaire: str = ""
    keywords: dict[str, str] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


def check_ascending(path: str, values: list[float], lines: list[int], what: str, lo: float, hi: float) -> None:
    """Angles must increase strictly and lie in [lo, hi]; the error names the offending line."""
    for i, v in enumerate(values):
        if not lo <= v <= hi:
            raise FormatError(path, f"line {lines[i]}", f"{what}: {v:g} deg is outside [{lo:g}, {hi:g}]")
        if i and v <= values[i - 1]:
            raise FormatError(
                path, f"line {lines[i]}", f"{what} must increase: {v:g} deg follows {values[i - 1]:g} deg"
            )


def _resample_rows(src_h: np.ndarray, rows: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Rows linearly interpolated along h at `at` (exact at knots: the table's own interpolant)."""
    if len(src_h) == 1:
        return np.repeat(rows[:1], len(at), axis=0)
    i = np.clip(np.searchsorted(src_h, at, side="right") - 1, 0, len(src_h) - 2)
    t = np.clip((at - src_h[i]) / (src_h[i + 1] - src_h[i]), 0.0, 1.0)[:, None]
    return rows[i] * (1.0 - t) + rows[i + 1] * t


def _unique(angles: np.ndarray) -> np.ndarray:
    return np.unique(np.round(angles, 9))


def expand_type_c(h: np.ndarray, rows: np.ndarray, symmetry: str) -> tuple[np.ndarray, np.ndarray]:
    """A type C table over its file range expanded to C = 0..360 inclusive.

    symmetry: "rotational" (one plane), "quadrant" (0-90: mirror about C90 then C180),
    "bilateral" (0-180: mirror about the C0-C180 plane), "bilateral-90-270" (90-270: mirror
    about the C90-C270 plane), "none" (0..360; a missing 360 repeats 0).
    """
    if symmetry == "rotational":
        return np.array([0.0, 360.0]), np.repeat(rows[:1], 2, axis=0)
    if symmetry == "none":
        if h[-1] < 360.0:
            h = np.append(h, 360.0)
            rows = np.concatenate([rows, rows[:1]])
        return h, rows
    if symmetry == "quadrant":
        images = np.concatenate([h, 180.0 - h, 180.0 + h, 360.0 - h])

        def fold(a: np.ndarray) -> np.ndarray:
            a = np.where(a > 180.0, 360.0 - a, a)
            return np.where(a > 90.0, 180.0 - a, a)

    elif symmetry == "bilateral":
        images = np.concatenate([h, 360.0 - h])

        def fold(a: np.ndarray) -> np.ndarray:
            return np.where(a > 180.0, 360.0 - a, a)

    elif symmetry == "bilateral-90-270":
        images = np.concatenate([h, np.mod(180.0 - h, 360.0)])

        def fold(a: np.ndarray) -> np.ndarray:
            return np.where((a >= 90.0) & (a <= 270.0), a, np.mod(180.0 - a, 360.0))

    else:
        raise ValueError(f"unknown symmetry {symmetry!r}")
    full = _unique(np.concatenate([images, [0.0, 360.0]]))
    full = full[(full >= 0.0) & (full <= 360.0)]
    return full, _resample_rows(h, rows, fold(full))


def mirror_negative(a: np.ndarray, rows: np.ndarray, axis: int) -> tuple[np.ndarray, np.ndarray]:
    """Angles 0..x mirrored to -x..x (I(-a) = I(a)) along `axis` of rows."""
    neg = -a[:0:-1] if a[0] == 0.0 else -a[::-1]
    idx = np.arange(len(a) - 1, 0, -1) if a[0] == 0.0 else np.arange(len(a) - 1, -1, -1)
    return np.concatenate([neg, a]), np.concatenate([np.take(rows, idx, axis=axis), rows], axis=axis)


def pad_zero(v: np.ndarray, rows: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """Extends the vertical axis (axis 1) to [lo, hi] with zero candela: past the file's last
    angle there is no light. Where the edge column is lit the drop takes CUT_DEG degrees."""
    left_v: list[float] = []
    right_v: list[float] = []
    if v[0] > lo:
        if rows[:, 0].any() and v[0] - CUT_DEG > lo:
            left_v = [lo, v[0] - CUT_DEG]
        else:
            left_v = [lo]
    if v[-1] < hi:
        if rows[:, -1].any() and v[-1] + CUT_DEG < hi:
            right_v = [v[-1] + CUT_DEG, hi]
        else:
            right_v = [hi]
    n = rows.shape[0]
    return (
        np.concatenate([left_v, v, right_v]),
        np.concatenate([np.zeros((n, len(left_v))), rows, np.zeros((n, len(right_v)))], axis=1),
    )


def type_c_symmetry(path: str, h: list[float], lines: list[int]) -> str:
    """The horizontal symmetry a type C angle list implies (IES); FormatError if none fits."""
    first, last = h[0], h[-1]
    if len(h) == 1:
        if first != 0.0:
            raise FormatError(path, f"line {lines[0]}", f"a single horizontal angle must be 0, not {first:g}")
        return "rotational"
    if first == 0.0 and last == 90.0:
        return "quadrant"
    if first == 0.0 and last == 180.0:
        return "bilateral"
    if first == 90.0 and last == 270.0:
        return "bilateral-90-270"
    if first == 0.0 and last == 360.0:
        return "none"
    if first == 0.0 and 180.0 < last < 360.0:
        # some writers leave out 360 (equal to 0); accept it where the gap is one of the file's steps
        gap = 360.0 - last
        steps = np.diff(h)
        if np.isclose(gap, steps[-1], rtol=1e-6, atol=1e-6) or np.isclose(gap, steps[0], rtol=1e-6, atol=1e-6):
            return "none"
    raise FormatError(
        path,
        f"line {lines[-1]}",
        f"horizontal angles {first:g}..{last:g}: a type C file runs 0 (one plane), 0-90, 0-180, 90-270 or 0-360",
    )


POLE_REL_TOL = 0.01  # values at one pole may differ by 1 % of the largest (measurement noise) ...
POLE_ABS_TOL = 1e-3  # ... or by 0.1 % of the table's maximum (a dark pole), before a warning


def _disagree(values: np.ndarray, table_max: float) -> bool:
    spread = float(values.max() - values.min())
    return spread > POLE_REL_TOL * float(values.max()) and spread > POLE_ABS_TOL * table_max


def pole_warnings(path: str, kind: str, h: np.ndarray, v: np.ndarray, rows: np.ndarray, lines: np.ndarray) -> list[str]:
    """Warnings where the file gives one direction several values: a pole of the angle grid
    (type C: gamma 0 and 180 across the C planes; type B: H -90 and 90 across the V planes)
    and, for a type C file listing both, the planes C0 and C360 (one half-plane).

    `h`, `v`: the file's angles (degrees); `rows[i, j]`: absolute candela at (h[i], v[j]) as the
    file gives them, before any symmetry expansion; `lines[i, j]`: the line each value is on.
    Such a table steps at the pole (the polar plot shows it; the illuminance straight under a
    type C luminaire reads as a hole or a spike) and is interpolated as it is."""
    h, v, rows = np.asarray(h, float), np.asarray(v, float), np.asarray(rows, float)
    table_max = float(rows.max()) if rows.size else 0.0
    out: list[str] = []
    if kind == "C":
        for j in sorted({0, len(v) - 1}):
            if v[j] not in (0.0, 180.0):
                continue
            col = rows[:, j]
            if len(col) > 1 and _disagree(col, table_max):
                a, b = int(np.argmax(col)), int(np.argmin(col))
                words = "straight down" if v[j] == 0.0 else "straight up"
                out.append(
                    f"{path} (line {lines[a, j]}, line {lines[b, j]}): gamma {v[j]:g} deg ({words}) is one "
                    f"direction but its candela differ across the {len(col)} C planes: {col[a]:.6g} cd at C{h[a]:g}, "
                    f"{col[b]:.6g} cd at C{h[b]:g}; the table steps there"
                )
        if len(h) > 1 and h[0] == 0.0 and h[-1] == 360.0:
            diff = np.abs(rows[0] - rows[-1])
            j = int(np.argmax(diff))
            if _disagree(np.array([rows[0, j], rows[-1, j]]), table_max):
                out.append(
                    f"{path} (line {lines[0, j]}, line {lines[-1, j]}): the C0 and C360 planes are one half-plane "
                    f"but differ: {rows[0, j]:.6g} cd and {rows[-1, j]:.6g} cd at gamma {v[j]:g} deg; "
                    f"both are kept, so the table steps at C0"
                )
    else:
        for i in sorted({0, len(h) - 1}):
            if h[i] not in (-90.0, 90.0):
                continue
            row = rows[i]
            if len(row) > 1 and _disagree(row, table_max):
                a, b = int(np.argmax(row)), int(np.argmin(row))
                out.append(
                    f"{path} (line {lines[i, a]}, line {lines[i, b]}): H {h[i]:g} deg (the pole, the luminaire's "
                    f"{'-' if h[i] > 0 else '+'}X axis) is one direction but its candela differ across the "
                    f"{len(row)} V planes: {row[a]:.6g} cd at V {v[a]:g}, {row[b]:.6g} cd at V {v[b]:g}; "
                    f"the table steps there"
                )
    return out


def check_finite(path: str, candela: np.ndarray, line: int) -> None:
    """Candela times the multipliers must fit float32 (files of 1e308 cd exist only in fuzzers)."""
    if not np.isfinite(candela).all() or (candela.size and candela.max() > 1e30):
        raise FormatError(path, f"line {line}", "candela values times the multipliers exceed 1e30 cd")


def finish_type_c(
    h: np.ndarray, v: np.ndarray, rows: np.ndarray, symmetry: str
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Symmetry expansion to C 0..360 and zero padding to gamma 0..180; float32 candela."""
    full_h, full_rows = expand_type_c(h, rows, symmetry)
    full_v, full_rows = pad_zero(v, full_rows, 0.0, 180.0)
    return full_h, full_v, full_rows.astype(np.float32)
