"""EULUMDAT (.ldt) photometric files read into `Photometry`.

EULUMDAT is line-oriented; line numbers (1-based) as the format defines them:
 1 company / format id, 2 Ityp, 3 Isym (0 none, 1 about the vertical axis, 2 about the
 C0-C180 plane, 3 about the C90-C270 plane, 4 about both), 4 Mc (C planes in 0..360),
 5 Dc, 6 Ng (intensities per plane), 7 Dg, 8 report number, 9 luminaire name,
 10 luminaire number, 11 file name, 12 date/user, 13-15 luminaire length (along C0),
 width (along C90), height in mm, 16-17 luminous area length / width (mm, width 0 = round),
 18-21 luminous area heights at C0/C90/C180/C270, 22 downward flux fraction %, 23 light
 output ratio LORL %, 24 conversion factor for intensities, 25 tilt during measurement,
 26 n lamp sets, then per set six lines (number of lamps, negative for absolute photometry;
 type; total lamp flux in lm; colour temperature; colour rendering; watts), then ten direct
 ratios, then Mc C angles, Ng gamma angles and the intensities in cd/klm, plane by plane.
 The stored planes depend on Isym: 0 all Mc, 1 one plane, 2 C0..C180, 3 C270..C360..C90,
 4 C0..C90.
From the angle lists on, numbers may share lines or be wrapped (whitespace or commas).

Intensities become candela as cd/klm x (flux of the first lamp set / 1000) x the conversion
factor; further lamp sets are alternative equipment and are kept in `extra`.
"""

from __future__ import annotations

import numpy as np

from patina.errors import FormatError
from patina.photometry.model import Opening, Photometry, check_ascending, check_finite, finish_type_c, pole_warnings
from patina.photometry.text import TokenStream, parse_int, parse_number, read_lines, tokens

SYMMETRY = {0: "none", 1: "rotational", 2: "bilateral", 3: "bilateral-90-270", 4: "quadrant"}
MAX_LAMP_SETS = 20


class _Lines:
    def __init__(self, path: str, lines: list[str]) -> None:
        self.path = path
        self.lines = lines

    def text(self, n: int) -> str:
        return self.lines[n - 1].strip()

    def number(self, n: int, what: str, blank: float | None = None) -> float:
        t = self.text(n)
        if not t and blank is not None:
            return blank
        if t.count(",") == 1 and "." not in t:
            t = t.replace(",", ".")  # a decimal comma, as some European tools write
        return parse_number(self.path, t, n, what)

    def integer(self, n: int, what: str) -> int:
        return parse_int(self.path, self.text(n), n, what)


def read_ldt(path: str) -> Photometry:
    path = str(path)
    raw = read_lines(path)
    while raw and not raw[-1].strip():
        raw.pop()
    if len(raw) < 26:
        raise FormatError(path, f"line {len(raw)}", f"the file ends after {len(raw)} lines; EULUMDAT has at least 42")
    f = _Lines(path, raw)
    ityp = f.integer(2, "type indicator Ityp")
    if ityp not in (0, 1, 2, 3):
        raise FormatError(path, "line 2", f"type indicator Ityp {ityp}: 0 to 3")
    isym = f.integer(3, "symmetry indicator Isym")
    if isym not in SYMMETRY:
        raise FormatError(path, "line 3", f"symmetry indicator Isym {isym}: 0 to 4")
    mc = f.integer(4, "number of C planes Mc")
    if mc < 1:
        raise FormatError(path, "line 4", f"number of C planes Mc {mc}: at least 1")
    if isym == 2 and mc % 2:
        raise FormatError(path, "line 4", f"Mc {mc} with Isym 2: Mc must be even (C0..C180 holds Mc/2 + 1 planes)")
    if isym in (3, 4) and mc % 4:
        raise FormatError(path, "line 4", f"Mc {mc} with Isym {isym}: Mc must be a multiple of 4")
    dc = f.number(5, "C plane distance Dc")
    ng = f.integer(6, "number of intensities per plane Ng")
    if ng < 1:
        raise FormatError(path, "line 6", f"number of intensities per plane Ng {ng}: at least 1")
    dg = f.number(7, "gamma distance Dg")
    dims = [f.number(n, what, blank=0.0) for n, what in zip(range(13, 22), _DIMENSIONS)]
    dff = f.number(22, "downward flux fraction", blank=0.0)
    lorl = f.number(23, "light output ratio LORL", blank=100.0)
    if not 0.0 <= lorl <= 1000.0:
        raise FormatError(path, "line 23", f"light output ratio {lorl:g} %: 0 to 100 (or a little over)")
    conversion = f.number(24, "conversion factor for intensities", blank=1.0)
    if conversion < 0:
        raise FormatError(path, "line 24", f"conversion factor {conversion:g} is negative")
    if conversion == 0:
        conversion = 1.0  # written as 0 by some tools that mean "none"
    tilt_deg = f.number(25, "tilt during measurement", blank=0.0)
    n_sets = f.integer(26, "number of lamp sets")
    if not 1 <= n_sets <= MAX_LAMP_SETS:
        raise FormatError(path, "line 26", f"number of lamp sets {n_sets}: 1 to {MAX_LAMP_SETS}")
    data_line = 27 + 6 * n_sets + 10
    if len(raw) < data_line:
        raise FormatError(
            path, f"line {len(raw)}", f"the file ends before the {n_sets} lamp sets and 10 direct ratios are complete"
        )
    sets = []
    for i in range(n_sets):
        base = 27 + 6 * i
        count = f.integer(base, f"number of lamps (set {i + 1})")
        flux = f.number(base + 2, f"total lamp flux (set {i + 1})")
        if count == 0:
            raise FormatError(path, f"line {base}", f"number of lamps (set {i + 1}) is 0")
        if flux <= 0:
            raise FormatError(path, f"line {base + 2}", f"total lamp flux (set {i + 1}) {flux:g} lm must be positive")
        watts = f.number(base + 5, f"wattage (set {i + 1})", blank=0.0)
        sets.append(
            {
                "lamps": count,
                "type": f.text(base + 1),
                "flux": flux,
                "colour": f.text(base + 3),
                "colour_rendering": f.text(base + 4),
                "watts": watts,
            }
        )
    direct_ratios = [f.number(27 + 6 * n_sets + k, "direct ratio", blank=0.0) for k in range(10)]

    planes = {0: mc, 1: 1, 2: mc // 2 + 1, 3: mc // 2 + 1, 4: mc // 4 + 1}[isym]
    stream = TokenStream(path, tokens(raw, data_line), len(raw))
    stream.require(mc + ng + planes * ng, f"{mc} C angles, {ng} gamma angles and {planes}x{ng} intensities")
    c, c_lines = stream.numbers(mc, "C angle")
    g, g_lines = stream.numbers(ng, "gamma angle")
    values, v_lines = stream.numbers(planes * ng, "luminous intensity")
    stream.expect_end(f"the {planes}x{ng} intensities")
    check_ascending(path, c, c_lines, "C angles", 0.0, 360.0)
    if c[0] != 0.0 or (mc > 1 and c[-1] >= 360.0):
        raise FormatError(path, f"line {c_lines[0]}", f"C angles {c[0]:g}..{c[-1]:g}: they run from 0 up to below 360")
    check_ascending(path, g, g_lines, "gamma angles", 0.0, 180.0)
    for value, ln in zip(values, v_lines):
        if value < 0:
            raise FormatError(path, f"line {ln}", f"luminous intensity {value:g} cd/klm is negative")

    rows = np.array(values, np.float64).reshape(planes, ng)
    value_lines = np.array(v_lines).reshape(planes, ng)
    c_arr = np.array(c)
    for index, angle in {2: [(mc // 2, 180.0)], 3: [(mc // 4, 90.0), (3 * mc // 4, 270.0)], 4: [(mc // 4, 90.0)]}.get(
        isym, []
    ):
        if abs(c_arr[index] - angle) > 1e-6:
            raise FormatError(
                path,
                f"line {c_lines[index]}",
                f"Isym {isym} needs C plane {index + 1} at {angle:g} deg, not {c_arr[index]:g}",
            )
    if isym == 0:
        h = c_arr
    elif isym == 1:
        h = np.array([0.0])
    elif isym == 2:
        h = c_arr[:planes]
    elif isym == 4:
        h = c_arr[:planes]
    else:
        # planes C270..C360(=C0)..C90 in file order; by the C90-C270 mirror they equal C270..C90 reversed
        index = (3 * mc // 4 + np.arange(planes)) % mc
        s = np.where(index >= 3 * mc // 4, c_arr[index] - 360.0, c_arr[index])
        h = 180.0 - s[::-1]
        rows = rows[::-1]
        value_lines = value_lines[::-1]

    first = sets[0]
    absolute = first["lamps"] < 0
    factor = first["flux"] / 1000.0 * conversion
    with np.errstate(over="ignore", invalid="ignore"):  # inf x 0: check_finite reports it
        rows = rows * factor
    check_finite(path, rows, 24)
    warnings = pole_warnings(path, "C", h, np.array(g), rows, value_lines)
    full_h, full_v, candela = finish_type_c(h, np.array(g), rows, SYMMETRY[isym])
    keywords = {
        "MANUFAC": f.text(1),
        "TEST": f.text(8),
        "LUMINAIRE": f.text(9),
        "LUMCAT": f.text(10),
        "DATE": f.text(12),
        "LAMP": first["type"],
    }
    return Photometry(
        path=path,
        format="EULUMDAT",
        version="EULUMDAT",
        type="C",
        symmetry=SYMMETRY[isym],
        h_deg=full_h,
        v_deg=full_v,
        candela=candela,
        file_h_deg=c_arr,
        file_v_deg=np.array(g),
        lumens=None if absolute else first["flux"],
        luminaire_lumens=first["flux"] * (1.0 if absolute else lorl / 100.0),  # as stated: no conversion factor
        lamps=abs(first["lamps"]),
        multiplier=factor,
        tilt=None,
        opening=_opening(dims),
        input_watts=first["watts"] or None,
        manufacturer=f.text(1),
        catalogue=f.text(10),
        luminaire=f.text(9),
        keywords={k: v for k, v in keywords.items() if v},
        extra={
            "ityp": ityp,
            "isym": isym,
            "dc": dc,
            "dg": dg,
            "downward_flux_fraction": dff,
            "light_output_ratio": lorl / 100.0,
            "conversion_factor": conversion,
            "measurement_tilt_deg": tilt_deg,
            "lamp_sets": sets,
            "direct_ratios": direct_ratios,
            "luminaire_size_m": [d / 1000.0 for d in dims[:3]],
        },
        warnings=warnings,
    )


_DIMENSIONS = (
    "luminaire length",
    "luminaire width",
    "luminaire height",
    "luminous area length",
    "luminous area width",
    "luminous area height C0",
    "luminous area height C90",
    "luminous area height C180",
    "luminous area height C270",
)


def _opening(dims: list[float]) -> Opening:
    length, width = dims[3] / 1000.0, dims[4] / 1000.0
    height = max(dims[5:9]) / 1000.0
    if length == 0 and width == 0:
        shape = "point"
    elif width == 0:
        shape = "disk"
        width = length
    else:
        shape = "rectangle" if height == 0 else "box"
    return Opening(width=width, length=length, height=height, shape=shape)
