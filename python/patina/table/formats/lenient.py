"""Reading a table for `patina validate`: a file whose only fault is some unusable values
(NaN, infinite, beyond float32) is read anyway, those values reported with their place
and masked as missing, so that validation lists them (exit 1) and runs its other checks
instead of refusing the file (exit 2) as every other command does.

Only that fault is forgiven: for .ptab and MERL the native reader runs first and checks
everything else (sizes, header, checksum); only when it stops at a value is the payload
read again here, at the offsets that reader has already verified.
"""

from __future__ import annotations

import math
import os
import struct

import numpy as np

from patina.errors import FormatError
from patina.file_names import printable
from patina.native import _core
from patina.table.brdf import Brdf
from patina.table.formats.astm import read_astm
from patina.table.formats.csv_table import read_csv
from patina.table.formats.loading import IMPORTERS, engine_read, locate, read_imported
from patina.table.formats.tabledata import BadValues, TableData, table_from_data

FLOAT32_MAX = float(np.finfo(np.float32).max)
_MERL_SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])  # brdf/merl.cpp's kScale
_MERL_CHANNELS = ("red", "green", "blue")
_PARAMETRIZATIONS = ("isotropic", "anisotropic", "halfdiff")
_CHANNEL_KINDS = ("mono", "rgb", "xyz", "spectral")


def _value_fault(e: FormatError) -> bool:
    """The native readers' messages for a bad value (not a bad knot or header field)."""
    return ("value" in e.problem and "not finite" in e.problem and "knot" not in e.problem) or (
        "too large for float32" in e.problem
    )


def read_reporting_bad_values(path: str | os.PathLike[str]) -> tuple[Brdf, BadValues]:
    """The file as a Brdf, and its bad values (count 0 for a clean file)."""
    given = os.fspath(path)
    path, side, kind = locate(given)
    try:
        if kind == "ptab":
            return Brdf(engine_read(_core.read_ptab, path), printable(given), "ptab"), BadValues()
        if kind == "merl":
            return Brdf(engine_read(_core.read_merl, path), printable(given), "merl"), BadValues()
    except FormatError as e:
        if not _value_fault(e):
            raise
        data = _ptab(path) if kind == "ptab" else _merl(path)
    else:
        if kind in IMPORTERS:  # binary formats whose readers refuse bad values outright
            data = read_imported(kind, path, side)
        elif kind == "csv":
            data = read_csv(path, report_bad=True)
        else:
            data = read_astm(path, resample=True, report_bad=True)
    try:
        table = table_from_data(data)
    except ValueError as e:
        raise FormatError(path, "table", str(e)) from None
    return Brdf(table, printable(given), kind), data.bad or BadValues()


def _deg(x: float) -> float:
    return round(math.degrees(float(x)), 3)


def _merl(path: str) -> TableData:
    """brdf/merl.cpp's layout (90 x 90 x 181 halfdiff knots, phi_d = 180 deg repeating 0),
    with non-finite and too large values masked instead of refused."""
    raw = np.fromfile(path, dtype="<f8", offset=12).reshape(3, 90, 90, 180)  # size checked by read_merl
    with np.errstate(over="ignore", invalid="ignore"):
        scaled = raw * _MERL_SCALE[:, None, None, None]
        bad = ~np.isfinite(scaled) | (scaled > FLOAT32_MAX)
    deg = math.pi / 180.0
    axes = [
        np.array([i * i / 90.0 * deg for i in range(90)], dtype=np.float32),
        np.array([j * deg for j in range(90)], dtype=np.float32),
        np.array([k * deg for k in range(181)], dtype=np.float32),
    ]
    report = BadValues()
    for c, h, d, p in np.argwhere(bad)[: BadValues.FIRST]:
        flat = np.ravel_multi_index((c, h, d, p), raw.shape)
        report.add(
            {
                "where": f"byte {12 + 8 * int(flat)}",
                "channel": _MERL_CHANNELS[c],
                "value": f"{float(raw[c, h, d, p]):g}",  # a string: JSON has no NaN
                "theta_h": _deg(axes[0][h]),
                "theta_d": _deg(axes[1][d]),
                "phi_d": _deg(axes[2][p]),
            }
        )
    report.count = int(bad.sum())
    values = np.where(bad, 0.0, scaled).transpose(1, 2, 3, 0)
    values = np.concatenate([values, values[:, :, :1]], axis=2)  # phi_d = 180 deg is phi_d = 0
    bad_points = bad.any(axis=0)
    bad_points = np.concatenate([bad_points, bad_points[:, :, :1]], axis=2)
    measured = (values >= 0).all(axis=-1) & ~bad_points
    values[~measured] = 0.0
    report.points = bad_points
    name = os.path.basename(path)
    return TableData(
        "halfdiff",
        axes,
        values.astype(np.float32),
        "rgb",
        provenance=f"MERL BRDF database .binary ({name}); {report.count} unusable values masked for validation",
        mask=None if measured.all() else measured,
        symmetry={"reciprocity"},
        bad=report,
    )


def _ptab(path: str) -> TableData:
    """docs/ptab.md's layout, read after _core.read_ptab verified everything but the values."""
    with open(path, "rb") as f:
        data = f.read()
    param, kind, symmetry, flags, dims, channels = struct.unpack_from("<6I", data, 12)  # after magic, version
    offset = 12 + 4 * 6
    lengths = struct.unpack_from(f"<{dims}I", data, offset)
    offset += 4 * dims
    texts = []
    for _ in range(2):  # units, provenance (UTF-8, checked by the native reader)
        (n,) = struct.unpack_from("<I", data, offset)
        texts.append(data[offset + 4 : offset + 4 + n].decode("utf-8"))
        offset += 4 + n
    axes = []
    for n in lengths:
        axes.append(np.frombuffer(data, "<f4", n, offset).copy())
        offset += 4 * n
    wavelengths = None
    if kind == 3:
        wavelengths = np.frombuffer(data, "<f4", channels, offset).copy()
        offset += 4 * channels
    points = math.prod(lengths)
    mask = None
    if flags & 1:
        mask = np.frombuffer(data, np.uint8, points, offset).astype(bool).reshape(lengths)
        offset += (points + 3) & ~3
    values = np.frombuffer(data, "<f4", points * channels, offset).reshape(*lengths, channels).copy()
    bad = ~np.isfinite(values)
    report = BadValues()
    for index in np.argwhere(bad)[: BadValues.FIRST]:
        flat = int(np.ravel_multi_index(tuple(index), values.shape))
        place = {name: _deg(axis[i]) for name, axis, i in zip(_core_axis_names(param), axes, index[:-1])}
        value = f"{float(values[tuple(index)]):g}"  # a string: JSON has no NaN
        report.add({"where": f"byte {offset + 4 * flat}", "channel": int(index[-1]), "value": value, **place})
    report.count = int(bad.sum())
    bad_points = bad.any(axis=-1)
    values[bad_points] = 0.0
    report.points = bad_points
    measured = ~bad_points if mask is None else mask & ~bad_points
    names = {1: "reciprocity", 2: "phi_mirror"}
    return TableData(
        _PARAMETRIZATIONS[param],
        axes,
        values,
        _CHANNEL_KINDS[kind],
        wavelengths=wavelengths,
        units=texts[0],
        provenance=texts[1],
        mask=measured,
        symmetry={n for bit, n in names.items() if symmetry & bit},
        bad=report,
    )


def _core_axis_names(param: int) -> tuple[str, ...]:
    return (
        ("theta_i", "theta_o", "phi_d"),
        ("theta_i", "phi_i", "theta_o", "phi_o"),
        ("theta_h", "theta_d", "phi_d"),
    )[param]
