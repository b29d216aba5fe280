"""IES LM-63 photometric files (1986, 1991, 1995, 2002 and 2019 headers) read into `Photometry`.

Layout: an optional version line (`IESNA:LM-63-1995`, `IESNA:LM-63-2002`, `IES:LM-63-2019`,
`IESNA91`, and the legacy spellings `IESNA95`, `IESNA:LM-63-95`, `IES LM-63-2002`; none in
1986 files), keyword lines `[KEY] value` (the value without its surrounding blanks) with
`[MORE]` continuing the previous keyword, a `TILT=` line (NONE, INCLUDE with the tilt block
following, or a file name read relative to this file), then numbers in any wrapping: lamps, lumens per lamp (-1:
absolute photometry), candela multiplier, vertical and horizontal angle counts, photometric
type (1 C, 2 B, 3 A), units (1 feet, 2 metres), opening width, length, height; ballast factor,
ballast-lamp photometric factor (1995 and older; "future use" in 2002, file generation type in
2019), input watts; the vertical angles, the horizontal angles, and the candela values, one
horizontal angle's vertical sweep after another.

Type A (automotive: polar axis along the luminaire's length) is refused: no light in Patina
is aimed that way and the files are rare; the error says so.
"""

from __future__ import annotations

import os
import re

import numpy as np

from patina.errors import FormatError
from patina.photometry.model import (
    Opening,
    Photometry,
    Tilt,
    check_ascending,
    check_finite,
    finish_type_c,
    mirror_negative,
    pad_zero,
    pole_warnings,
    type_c_symmetry,
)
from patina.photometry.text import TokenStream, read_lines, tokens

_KEYWORD = re.compile(r"^\s*\[([^\]]*)\]\s?(.*)$")
FEET = 0.3048


# `IESNA:LM-63-1995`, `IES:LM-63-2019`, `IESNA LM-63-2002`, `IESNA:LM-63-95`; `IESNA91`, `IESNA95`, `IESNA:2002`
_VERSION = re.compile(r"^IES(?:NA)?\s*[:\-]?\s*(?:LM\s*-?\s*63\s*-?\s*)?(\d{4}|\d{2})(?!\d)")


def _version(first: str) -> str | None:
    """The edition a version line names, as "LM-63-yyyy"; None where the first line is not one (1986 files)."""
    m = _VERSION.match(first.strip().upper())
    if not m:
        return None
    year = int(m.group(1))
    if len(m.group(1)) == 2:
        year += 1900 if year >= 50 else 2000
    return f"LM-63-{year}" if 1986 <= year <= 2099 else None


def _read_tilt(path: str, stream: TokenStream) -> Tilt:
    geometry = stream.integer("lamp-to-luminaire geometry")
    if geometry not in (1, 2, 3):
        raise FormatError(
            path, f"line {stream.toks[stream.pos - 1].line}", f"lamp-to-luminaire geometry {geometry}: 1, 2 or 3"
        )
    line = stream.line
    n = stream.integer("number of tilt angles")
    if n < 1:
        raise FormatError(path, f"line {line}", f"number of tilt angles {n}: at least 1")
    stream.require(2 * n, "tilt angles and factors")
    angles, lines = stream.numbers(n, "tilt angle")
    check_ascending(path, angles, lines, "tilt angles", 0.0, 180.0)
    factors, flines = stream.numbers(n, "tilt multiplying factor")
    for f, ln in zip(factors, flines):
        if f < 0:
            raise FormatError(path, f"line {ln}", f"tilt multiplying factor {f:g} is negative")
    return Tilt(geometry, np.array(angles), np.array(factors))


def _tilt_file(path: str, name: str, line: int) -> Tilt:
    tilt_path = os.path.join(os.path.dirname(os.path.abspath(path)), name)
    if not os.path.isfile(tilt_path):
        raise FormatError(path, f"line {line}", f"TILT={name}: the tilt file {tilt_path} does not exist")
    lines = read_lines(tilt_path)
    stream = TokenStream(tilt_path, tokens(lines, 1), len(lines))
    tilt = _read_tilt(tilt_path, stream)
    stream.expect_end("the tilt data")
    return tilt


def _opening(w: float, ln: float, h: float, scale: float) -> Opening:
    w, ln, h = w * scale, ln * scale, h * scale
    if w == 0 and ln == 0 and h == 0:
        shape = "point"
    elif w > 0 and ln > 0:
        shape = "rectangle" if h == 0 else "box" if h > 0 else "other"
    elif w < 0 and ln < 0:
        if h == 0:
            shape = "disk" if w == ln else "ellipse"
        elif h < 0:
            shape = "sphere" if w == ln == h else "ellipsoid"
        else:
            shape = "cylinder"
    else:
        shape = "other"
    return Opening(width=w, length=ln, height=h, shape=shape)


def read_ies(path: str) -> Photometry:
    path = str(path)
    lines = read_lines(path)
    version = _version(lines[0]) if lines else None
    first = 2 if version else 1
    warnings: list[str] = []
    if version is None and lines and re.match(r"^(IESNA|IES\s*:)", lines[0].strip().upper()):
        warnings.append(
            f"{path} (line 1): {lines[0].strip()[:40]!r} looks like a version line but names no LM-63 edition; "
            "read as an LM-63-1986 file (the line kept as text)"
        )
    version = version or "LM-63-1986"
    year = int(version[6:])
    keywords: dict[str, str] = {}
    text: list[str] = []
    last_key: str | None = None
    tilt_line = 0
    for number in range(first, len(lines) + 1):
        line = lines[number - 1]
        if line.lstrip().upper().startswith("TILT"):
            tilt_line = number
            break
        m = _KEYWORD.match(line)
        if m:
            key, value = m.group(1).strip().upper(), m.group(2).strip()
            if key == "MORE" and last_key is not None:
                keywords[last_key] += "\n" + value
            else:
                last_key = key if key != "MORE" else None
                keywords[key] = value if key not in keywords else keywords[key] + "\n" + value
        elif line.strip():
            text.append(line.strip())
    if not tilt_line:
        raise FormatError(
            path, f"line {len(lines)}", "no TILT= line: not an IES LM-63 file, or the header is cut short"
        )
    tilt_spec = lines[tilt_line - 1].strip()
    eq = tilt_spec.find("=")
    if eq < 0:
        raise FormatError(
            path, f"line {tilt_line}", f"{tilt_spec[:40]!r}: expected TILT=NONE, TILT=INCLUDE or TILT=<file>"
        )
    tilt_value = tilt_spec[eq + 1 :].strip()
    stream = TokenStream(path, tokens(lines, tilt_line + 1), len(lines))
    tilt: Tilt | None = None
    if tilt_value.upper() == "INCLUDE":
        tilt = _read_tilt(path, stream)
    elif tilt_value.upper() != "NONE":
        if not tilt_value:
            raise FormatError(path, f"line {tilt_line}", "TILT= names no file")
        tilt = _tilt_file(path, tilt_value, tilt_line)

    line = stream.line
    lamps = stream.integer("number of lamps")
    if lamps < 1:
        raise FormatError(path, f"line {line}", f"number of lamps {lamps}: at least 1")
    line = stream.line
    lumens_per_lamp = stream.number("lumens per lamp")
    if lumens_per_lamp <= 0 and lumens_per_lamp != -1:
        raise FormatError(
            path, f"line {line}", f"lumens per lamp {lumens_per_lamp:g}: positive, or -1 for absolute photometry"
        )
    line = multiplier_line = stream.line
    multiplier = stream.number("candela multiplier")
    if multiplier <= 0:
        raise FormatError(path, f"line {line}", f"candela multiplier {multiplier:g} must be positive")
    line = stream.line
    n_v = stream.integer("number of vertical angles")
    n_h = stream.integer("number of horizontal angles")
    if n_v < 1 or n_h < 1:
        raise FormatError(path, f"line {line}", f"angle counts {n_v} vertical, {n_h} horizontal: at least 1 each")
    line = stream.line
    ptype = stream.integer("photometric type")
    if ptype == 3:
        raise FormatError(
            path, f"line {line}", "photometric type 3 (type A, automotive) is not supported: use type B or C"
        )
    if ptype not in (1, 2):
        raise FormatError(path, f"line {line}", f"photometric type {ptype}: 1 (C), 2 (B) or 3 (A)")
    line = stream.line
    units = stream.integer("units type")
    if units not in (1, 2):
        raise FormatError(path, f"line {line}", f"units type {units}: 1 (feet) or 2 (metres)")
    width = stream.number("luminous opening width")
    length = stream.number("luminous opening length")
    height = stream.number("luminous opening height")
    line = stream.line
    ballast = stream.number("ballast factor")
    if ballast <= 0:
        raise FormatError(path, f"line {line}", f"ballast factor {ballast:g} must be positive")
    line = stream.line
    second = stream.number("ballast-lamp photometric factor")
    old = year < 2002  # 1986, 1991, 1995: the ballast-lamp photometric factor applies
    if old and second <= 0:
        raise FormatError(path, f"line {line}", f"ballast-lamp photometric factor {second:g} must be positive")
    watts = stream.number("input watts")

    stream.require(
        n_v + n_h + n_v * n_h, f"{n_v} vertical angles, {n_h} horizontal angles and {n_v}x{n_h} candela values"
    )
    v, v_lines = stream.numbers(n_v, "vertical angle")
    h, h_lines = stream.numbers(n_h, "horizontal angle")
    cd, cd_lines = stream.numbers(n_v * n_h, "candela value")
    stream.expect_end(f"the {n_v}x{n_h} candela values")
    for value, ln in zip(cd, cd_lines):
        if value < 0:
            raise FormatError(path, f"line {ln}", f"candela value {value:g} is negative")

    factor = multiplier * ballast * (second if old else 1.0)
    with np.errstate(over="ignore", invalid="ignore"):  # inf x 0: check_finite reports it
        rows = np.array(cd, np.float64).reshape(n_h, n_v) * factor
    check_finite(path, rows, multiplier_line)
    cd_line_of = np.array(cd_lines).reshape(n_h, n_v)
    if ptype == 1:
        kind = "C"
        check_ascending(path, v, v_lines, "vertical angles", 0.0, 180.0)
        check_ascending(path, h, h_lines, "horizontal angles", 0.0, 360.0)
        symmetry = type_c_symmetry(path, h, h_lines)
        warnings += pole_warnings(path, "C", np.array(h), np.array(v), rows, cd_line_of)
        full_h, full_v, candela = finish_type_c(np.array(h), np.array(v), rows, symmetry)
    else:
        kind = "B"
        check_ascending(path, v, v_lines, "vertical angles", -90.0, 90.0)
        check_ascending(path, h, h_lines, "horizontal angles", -90.0, 90.0)
        for name, a, ln in (("horizontal", h, h_lines), ("vertical", v, v_lines)):
            if a[0] not in (-90.0, 0.0) or a[-1] != 90.0:
                raise FormatError(
                    path, f"line {ln[-1]}", f"type B {name} angles {a[0]:g}..{a[-1]:g}: -90..90, or 0..90 if symmetric"
                )
        warnings += pole_warnings(path, "B", np.array(h), np.array(v), rows, cd_line_of)
        full_h, full_v, candela = expand_type_b(np.array(h), np.array(v), rows)
        symmetry = {
            (True, True): "quadrant",
            (True, False): "lateral",
            (False, True): "vertical",
            (False, False): "none",
        }[(h[0] == 0.0, v[0] == 0.0)]

    lumens = None if lumens_per_lamp == -1 else lamps * lumens_per_lamp
    return Photometry(
        path=path,
        format="IES",
        version=version,
        type=kind,
        symmetry=symmetry,
        h_deg=full_h,
        v_deg=full_v,
        candela=candela,
        file_h_deg=np.array(h),
        file_v_deg=np.array(v),
        lumens=lumens,
        luminaire_lumens=None,  # LM-63 states none: the table's flux against `lumens` is the light output ratio
        lamps=lamps,
        multiplier=factor,
        tilt=tilt,
        opening=_opening(width, length, height, FEET if units == 1 else 1.0),
        input_watts=watts,
        manufacturer=keywords.get("MANUFAC", ""),
        catalogue=keywords.get("LUMCAT", ""),
        luminaire=keywords.get("LUMINAIRE", ""),
        keywords=keywords,
        extra={
            "candela_multiplier": multiplier,
            "ballast_factor": ballast,
            "units": "feet" if units == 1 else "metres",
            **({"ballast_lamp_factor": second} if old else {}),
            **({"file_generation_type": second} if year >= 2019 else {}),
            **({"text": "\n".join(text)} if text else {}),
        },
        warnings=warnings,
    )


def expand_type_b(h: np.ndarray, v: np.ndarray, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Type B: H 0..90 mirrored to -90..90 (lateral symmetry), V 0..90 mirrored to -90..90
    (symmetry about the horizontal plane), then V padded with zero to -180..180 (behind the
    luminaire: no data, no light)."""
    if h[0] == 0.0:
        h, rows = mirror_negative(h, rows, axis=0)
    if v[0] == 0.0:
        v, rows = mirror_negative(v, rows, axis=1)
    v, rows = pad_zero(v, rows, -180.0, 180.0)
    return h, v, rows.astype(np.float32)
