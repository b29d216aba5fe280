"""Road surface reflection tables (r-tables: reduced luminance coefficients, CIE 144:2001 and
EN 13201-3) read from a documented text file (docs/lighting.md):

    # comments anywhere after '#'
    name: my R3 measurement          (optional header lines `key: value`: name, q0, source)
    beta: 0 2 5 10 15 20 25 30 35 40 45 60 75 90 105 120 135 150 165 180
    0     294 294 294 ...            (one row per tan gamma: tan gamma, then one value per beta)
    0.25  326 326 321 ...

Values are r x 10^4 in 1/sr, as the CIE publishes its tables: r(beta, tan gamma) =
q(beta, gamma) cos^3 gamma, the luminance of the surface per lux of horizontal illuminance's
I / H^2 (L = sum of I r / H^2). beta in degrees (0 to 180, ascending), tan gamma from 0
ascending. Every cell must be present (no holes) and non-negative; points beyond the last
tan gamma reflect nothing (the CIE's tables end where r is negligible). The CIE's standard
tables (R1-R4, C1-C2, N1-N4) are copyrighted: Patina ships none; bring your own measured or
licensed table in this format. tools/make_rtable.py writes a synthetic example.
"""

from __future__ import annotations

import itertools
import os
from dataclasses import dataclass, field

import numpy as np

from patina.atomic import write_text
from patina.errors import FormatError

MAX_BYTES = 1 << 20  # an r-table is a few kilobytes; more is not an r-table
MAX_ROWS = 1000
MAX_COLUMNS = 361
HEADER_KEYS = ("name", "q0", "source")
SCALE = 1e-4  # the file's values are r x 10^4
MISSING_HINT = (
    "an r-table is a text file (docs/lighting.md); the CIE's R1-R4 / C1-C2 tables are not bundled: use your own"
)


@dataclass(frozen=True)
class RTable:
    path: str
    beta_deg: np.ndarray  # (nb,) ascending in [0, 180]
    tan_gamma: np.ndarray  # (nt,) ascending from 0
    r: np.ndarray  # (nt, nb) in 1/sr (the file's values x 10^-4)
    header: dict[str, str] = field(default_factory=dict)

    def __call__(self, beta_deg: np.ndarray, tan_gamma: np.ndarray) -> np.ndarray:
        """r (1/sr) by bilinear interpolation in (tan gamma, beta); beta folded into [0, 180]
        (the surface is symmetric about the plane of observation); 0 beyond the last row."""
        b = np.abs(np.mod(np.asarray(beta_deg, np.float64) + 180.0, 360.0) - 180.0)
        t = np.asarray(tan_gamma, np.float64)
        ti = np.clip(np.searchsorted(self.tan_gamma, t, side="right") - 1, 0, max(len(self.tan_gamma) - 2, 0))
        bi = np.clip(np.searchsorted(self.beta_deg, b, side="right") - 1, 0, max(len(self.beta_deg) - 2, 0))
        if len(self.tan_gamma) > 1:
            ft = np.clip((t - self.tan_gamma[ti]) / (self.tan_gamma[ti + 1] - self.tan_gamma[ti]), 0, 1)
        else:
            ft = np.zeros_like(t)
        if len(self.beta_deg) > 1:
            fb = np.clip((b - self.beta_deg[bi]) / (self.beta_deg[bi + 1] - self.beta_deg[bi]), 0, 1)
        else:
            fb = np.zeros_like(b)
        t1, b1 = np.minimum(ti + 1, len(self.tan_gamma) - 1), np.minimum(bi + 1, len(self.beta_deg) - 1)
        r = self.r
        out = (1 - ft) * ((1 - fb) * r[ti, bi] + fb * r[ti, b1]) + ft * ((1 - fb) * r[t1, bi] + fb * r[t1, b1])
        return np.where(t <= self.tan_gamma[-1] * (1 + 1e-12), out, 0.0)

    def q0(self) -> float:
        """The average luminance coefficient: q = r / cos^3 gamma averaged over the solid angle
        of the table's incidences (CIE 144), by the trapezoid rule over its own knots."""
        gamma = np.arctan(self.tan_gamma)
        q = self.r / np.cos(gamma)[:, None] ** 3
        # dOmega = sin(gamma) dgamma dbeta, beta over [0, 180] (the other half is the mirror)
        over_beta = np.trapezoid(q, np.radians(self.beta_deg), axis=1) if len(self.beta_deg) > 1 else q[:, 0] * np.pi
        num = np.trapezoid(over_beta * np.sin(gamma), gamma) if len(gamma) > 1 else 0.0
        den = np.pi * (1 - np.cos(gamma[-1]))
        return float(num / den) if den > 0 else float(q[0, 0])


def _numbers(path: str, line_no: int, words: list[str]) -> list[float]:
    out = []
    for k, w in enumerate(words):
        try:
            v = float(w)
        except ValueError:
            problem = "a hole (no value)" if w in ("-", "*", "--", "n/a", "NA") else f"'{w[:20]}' is not a number"
            raise FormatError(path, f"line {line_no}, value {k + 1}", problem) from None
        if not np.isfinite(v):
            raise FormatError(path, f"line {line_no}, value {k + 1}", f"'{w[:20]}' is not finite")
        out.append(v)
    return out


def read_rtable(path: str | os.PathLike) -> RTable:
    """Reads an r-table; every problem raises FormatError naming the line and the value."""
    path = os.fspath(path)
    try:
        size = os.path.getsize(path)
    except OSError:
        raise FormatError(path, "", f"no such file: {MISSING_HINT}") from None
    if size > MAX_BYTES:
        raise FormatError(path, "", f"{size} bytes; an r-table has at most {MAX_BYTES}")
    with open(path, "rb") as f:
        raw = f.read(MAX_BYTES + 1)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise FormatError(path, f"byte {e.start}", "not UTF-8 text") from None
    header: dict[str, str] = {}
    beta: list[float] | None = None
    tans: list[float] = []
    rows: list[list[float]] = []
    for line_no, line in enumerate(text.splitlines(), 1):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        key, colon, rest = content.partition(":")
        key = key.strip().lower()
        if colon and key == "beta":
            if beta is not None:
                raise FormatError(path, f"line {line_no}", "a second 'beta:' line")
            beta = _numbers(path, line_no, rest.split())
            _check_axis(path, f"line {line_no}", beta, "beta", 0.0, 180.0, MAX_COLUMNS)
            continue
        if colon and key in HEADER_KEYS:
            if beta is not None:
                raise FormatError(path, f"line {line_no}", f"'{key}:' must come before the 'beta:' line")
            header[key] = rest.strip()
            continue
        if colon:
            raise FormatError(
                path, f"line {line_no}", f"unknown header '{key[:30]}' (expected {', '.join(HEADER_KEYS)}, beta)"
            )
        if beta is None:
            raise FormatError(path, f"line {line_no}", "a row before the 'beta:' line naming the columns")
        values = _numbers(path, line_no, content.replace(",", " ").split())
        if len(values) != len(beta) + 1:
            have = len(values) - 1
            raise FormatError(
                path, f"line {line_no}", f"{have} values for {len(beta)} beta columns: an r-table may have no holes"
            )
        if len(rows) >= MAX_ROWS:
            raise FormatError(path, f"line {line_no}", f"more than {MAX_ROWS} rows")
        negative = [k for k, v in enumerate(values[1:]) if v < 0]
        if negative:
            k = negative[0]
            raise FormatError(path, f"line {line_no}, beta {beta[k]:g}", f"negative value {values[k + 1]:g}")
        tans.append(values[0])
        rows.append(values[1:])
    if beta is None:
        raise FormatError(path, "", f"no 'beta:' line: {MISSING_HINT}")
    if not rows:
        raise FormatError(path, "", "no rows of tan gamma")
    _check_axis(path, "tan gamma (first column)", tans, "tan gamma", 0.0, 1e3, MAX_ROWS)
    if tans[0] != 0:
        raise FormatError(path, "tan gamma (first column)", f"the first row must be tan gamma 0, got {tans[0]:g}")
    if "q0" in header:
        try:
            float(header["q0"])
        except ValueError:
            raise FormatError(path, "q0", f"'{header['q0'][:20]}' is not a number") from None
    return RTable(path, np.array(beta), np.array(tans), np.array(rows) * SCALE, header)


def _check_axis(path: str, where: str, values: list[float], name: str, lo: float, hi: float, most: int) -> None:
    if not values:
        raise FormatError(path, where, f"no {name} values")
    if len(values) > most:
        raise FormatError(path, where, f"{len(values)} {name} values; at most {most}")
    if min(values) < lo or max(values) > hi:
        raise FormatError(path, where, f"{name} must lie in [{lo:g}, {hi:g}]")
    if any(b <= a for a, b in itertools.pairwise(values)):
        raise FormatError(path, where, f"{name} values must be strictly ascending")


def write_rtable(
    path: str, table_e4: np.ndarray, beta_deg: np.ndarray, tan_gamma: np.ndarray, header: dict[str, str]
) -> str:
    """The text of an r-table file (values already x 10^4), written to `path` atomically."""
    lines = ["# r-table: reduced luminance coefficients r x 10^4 (1/sr), rows tan gamma, columns beta (degrees)"]
    lines += [f"{k}: {v}" for k, v in header.items()]
    lines.append("beta: " + " ".join(f"{b:g}" for b in beta_deg))
    for t, row in zip(tan_gamma, table_e4):
        lines.append(f"{t:<5g} " + " ".join(f"{v:g}" for v in row))
    text = "\n".join(lines) + "\n"
    write_text(path, text)
    return text
