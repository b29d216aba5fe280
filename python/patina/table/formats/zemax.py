"""Zemax OpticStudio / LightTools tabular BSDF text (the "BSDF Data Interchange" format of
Radiant Imaging, specified in Zemax's knowledge base: "Zemax Tabular BSDF data file
format", R. Rykowski).

    # comments
    Source Measured
    Symmetry PlaneSymmetrical | Asymmetrical | Asymmetrical4D
    SpectralContent Monochrome | XYZ | RGB
    ScatterType BRDF | BTDF
    SampleRotation N, then N angles; AngleOfIncidence N, then N angles;
    ScatterAzimuth N, then N angles; ScatterRadial N, then N angles (degrees)
    then per channel: a label (Monochrome, TristimulusX/Y/Z, or R/G/B), DataBegin,
    for each rotation and angle of incidence "TIS value" and azimuth-by-radial values,
    DataEnd.

Scatter directions are given about the specular direction: radial 0 is the specular
direction, azimuth 0 points from it towards the surface normal, azimuths increasing
counter-clockwise (seen from above); a plane-symmetrical file gives azimuths 0-180 and
the other half mirrors them. Values are the BRDF in 1/sr (no cosine). The measured
directions, scattered over the hemisphere, are resampled onto a Patina grid
(formats/resample.py) with the error in the provenance: isotropic (theta_i, theta_o,
phi_d) for one sample rotation, anisotropic for Asymmetrical4D. A BTDF file is refused:
Patina tables are reflection.
"""

from __future__ import annotations

import math
from typing import NoReturn

import numpy as np

from patina.errors import FormatError
from patina.table.formats.measurement_noise import checked_measurement
from patina.table.formats.resample import CannotResample, resample
from patina.table.formats.tabledata import TableData
from patina.table.formats.whole_file import read_whole_file

MAX_FILE_BYTES = 256 << 20
MAX_POINTS = 2_000_000
LISTS = ("samplerotation", "angleofincidence", "scatterazimuth", "scatterradial")
LABELS = {
    "monochrome": "mono",
    "tristimulusx": "X",
    "tristimulusy": "Y",
    "tristimulusz": "Z",
    "tristimulusr": "R",
    "tristimulusg": "G",
    "tristimulusb": "B",
    "red": "R",
    "green": "G",
    "blue": "B",
}


class _Lines:
    """The file's lines without comments and blanks, with their 1-based numbers."""

    def __init__(self, path: str, text: str) -> None:
        self.path = path
        self.lines = [
            (n + 1, line.strip())
            for n, line in enumerate(text.splitlines())
            if line.strip() and not line.lstrip().startswith("#")
        ]
        self.at = 0

    def fail(self, problem: str, line: int | None = None) -> FormatError:
        if line is None:
            line = self.lines[min(self.at, len(self.lines) - 1)][0] if self.lines else 1
        return FormatError(self.path, f"line {line}", problem)

    def next(self, what: str) -> tuple[int, str]:
        if self.at >= len(self.lines):
            raise FormatError(self.path, "end of file", f"the file ends where {what} was expected")
        self.at += 1
        return self.lines[self.at - 1]

    def numbers(self, count: int, what: str) -> np.ndarray:
        out: list[float] = []
        while len(out) < count:
            number, line = self.next(f"{count} numbers ({what})")
            for token in line.replace(",", " ").split():
                try:
                    value = float(token)
                except ValueError:
                    raise self.fail(f"'{token[:30]}' is not a number ({what})", number) from None
                if not math.isfinite(value):
                    raise self.fail(f"{token} is not finite ({what})", number)
                out.append(value)
        if len(out) != count:
            raise self.fail(f"{len(out)} numbers where {count} were expected ({what})")
        return np.array(out)


def _header(src: _Lines) -> tuple[dict[str, str], dict[str, np.ndarray]]:
    words: dict[str, str] = {}
    lists: dict[str, np.ndarray] = {}
    while len(lists) < len(LISTS):
        number, line = src.next("the header keywords")
        key, _, rest = line.partition(" ")
        key, rest = key.lower(), rest.strip()
        if key in LISTS:
            try:
                count = int(rest)
            except ValueError:
                raise src.fail(f"{key}: '{rest[:30]}' is not a count", number) from None
            if not 1 <= count <= 100000:
                raise src.fail(f"{key}: count {count} outside 1-100000", number)
            lists[key] = src.numbers(count, key)
        elif key in ("source", "symmetry", "spectralcontent", "scattertype"):
            words[key] = rest.lower()
        else:
            raise src.fail(f"unexpected '{line[:40]}' in the header", number)
    return words, lists


def _blocks(src: _Lines, lists: dict[str, np.ndarray]) -> tuple[dict[str, np.ndarray], list[str]]:
    """The data blocks by channel, and the notes of the measurement noise set to 0 in them."""
    n_rot, n_aoi = lists["samplerotation"].size, lists["angleofincidence"].size
    n_az, n_rad = lists["scatterazimuth"].size, lists["scatterradial"].size
    if n_rot * n_aoi * n_az * n_rad > MAX_POINTS:
        raise src.fail(f"{n_rot * n_aoi * n_az * n_rad} measured directions: more than {MAX_POINTS}")
    blocks: dict[str, np.ndarray] = {}
    notes: list[str] = []
    while src.at < len(src.lines):
        number, label = src.next("a data label")
        channel = LABELS.get(label.lower())
        if channel is None:
            raise src.fail(f"'{label[:40]}': expected Monochrome, TristimulusX/Y/Z or a colour name", number)
        number, line = src.next("DataBegin")
        if line.lower() != "databegin":
            raise src.fail(f"expected DataBegin, found '{line[:40]}'", number)
        data = np.empty((n_rot, n_aoi, n_az, n_rad))
        tis_lines = np.empty((n_rot, n_aoi), dtype=int)
        for r in range(n_rot):
            for a in range(n_aoi):
                number, line = src.next("TIS")
                tis_lines[r, a] = number
                if not line.lower().startswith("tis"):
                    raise src.fail(f"expected 'TIS value' before each angle of incidence, found '{line[:40]}'", number)
                data[r, a] = src.numbers(n_az * n_rad, f"{label} data").reshape(n_az, n_rad)
        number, line = src.next("DataEnd")
        if line.lower() != "dataend":
            raise src.fail(f"expected DataEnd, found '{line[:40]}'", number)

        def refuse(first: int, problem: str, data=data, tis_lines=tis_lines, label=label) -> NoReturn:
            row, value = divmod(first, n_az * n_rad)
            shown = f"{label} value {value + 1} after this TIS line: {data.flat[first]:g}: {problem}"
            raise src.fail(shown, int(tis_lines.flat[row]))

        blocks[channel], noise = checked_measurement(data, refuse)
        if noise:
            notes.append(f"{label}: {noise}")
    if not blocks:
        raise FormatError(src.path, "end of file", "no data block (a label, DataBegin ... DataEnd)")
    return blocks, notes


def _channels(path: str, blocks: dict[str, np.ndarray]) -> tuple[np.ndarray, str]:
    """The blocks as (..., channels) values and their kind: mono, xyz or rgb."""
    for order, kind in ((("X", "Y", "Z"), "xyz"), (("R", "G", "B"), "rgb"), (("mono",), "mono")):
        if all(c in blocks for c in order):
            return np.stack([blocks[c] for c in order], axis=-1), kind
    raise FormatError(path, "data", f"blocks {sorted(blocks)}: expected Monochrome, or X, Y and Z, or R, G and B")


def scatter_directions(theta_i: np.ndarray, phi_i: np.ndarray, azimuth: np.ndarray, radial: np.ndarray) -> np.ndarray:
    """Unit scatter directions about the specular direction (angles in radians, broadcast)."""
    st, ct = np.sin(theta_i), np.cos(theta_i)
    cp, sp = np.cos(phi_i), np.sin(phi_i)
    spec = np.stack([-st * cp, -st * sp, ct], axis=-1)
    # azimuth 0: from the specular direction towards the normal (for normal incidence: towards -wi's azimuth)
    towards = np.stack([st * ct * cp, st * ct * sp, st * st], axis=-1)
    fallback = np.stack([cp, sp, np.zeros_like(cp)], axis=-1)
    norm = np.linalg.norm(towards, axis=-1, keepdims=True)
    t0 = np.where(norm > 1e-9, towards / np.maximum(norm, 1e-300), fallback)
    t1 = np.cross(spec, t0)
    ca, sa, cr, sr = np.cos(azimuth), np.sin(azimuth), np.cos(radial), np.sin(radial)
    return cr[..., None] * spec + sr[..., None] * (ca[..., None] * t0 + sa[..., None] * t1)


def read_zemax(path: str) -> TableData:
    raw = read_whole_file(path, MAX_FILE_BYTES)
    text = raw.decode("utf-8-sig", errors="replace")
    src = _Lines(path, text)
    words, lists = _header(src)
    if words.get("scattertype", "brdf") != "brdf":
        raise FormatError(
            path, "ScatterType", f"{words['scattertype'].upper()}: only BRDF data (Patina tables are reflection)"
        )
    symmetry = words.get("symmetry", "planesymmetrical")
    if symmetry not in ("planesymmetrical", "asymmetrical", "asymmetrical4d"):
        raise FormatError(path, "Symmetry", f"'{symmetry}': expected PlaneSymmetrical, Asymmetrical or Asymmetrical4D")
    blocks, noise = _blocks(src, lists)
    channels, kind = _channels(path, blocks)
    rot, aoi, az, rad = (np.radians(lists[k]) for k in LISTS)
    if np.any(aoi < 0) or np.any(aoi >= math.pi / 2) or np.any(rad < 0) or np.any(rad > math.pi):
        raise FormatError(path, "AngleOfIncidence/ScatterRadial", "angles outside [0, 90) and [0, 180] degrees")
    r, a, z, d = np.meshgrid(rot, aoi, az, rad, indexing="ij")
    values = channels.reshape(-1, channels.shape[-1])
    pieces = [(r, z)]
    if symmetry == "planesymmetrical":
        pieces.append((r, -z))  # the mirrored half
    coords, vals = [], []
    for rr, zz in pieces:
        phi_i = -rr  # a sample turned by rho sees the light from azimuth -rho
        wo = scatter_directions(a, phi_i, zz, d).reshape(-1, 3)
        keep = wo[:, 2] > 1e-6
        ti, pi = a.ravel()[keep], np.mod(phi_i.ravel()[keep], 2 * math.pi)
        to = np.arccos(np.clip(wo[keep, 2], -1, 1))
        po = np.mod(np.arctan2(wo[keep, 1], wo[keep, 0]), 2 * math.pi)
        if symmetry == "asymmetrical4d":
            coords.append(np.stack([ti, pi, to, po], axis=1))
        else:
            pd = np.abs(np.mod(po - pi + math.pi, 2 * math.pi) - math.pi)
            coords.append(np.stack([ti, to, pd], axis=1))
        vals.append(values[keep])
    names = (
        ["theta_i", "phi_i", "theta_o", "phi_o"] if symmetry == "asymmetrical4d" else ["theta_i", "theta_o", "phi_d"]
    )
    try:
        axes, grid, error = resample(np.concatenate(coords), np.concatenate(vals), names)
    except CannotResample as e:
        raise FormatError(path, "data", str(e)) from None
    return TableData(
        parametrization="anisotropic" if symmetry == "asymmetrical4d" else "isotropic",
        axes=axes,
        values=grid.astype(np.float32),
        channel_kind=kind,
        provenance="; ".join([f"Zemax tabular BSDF ({symmetry}, {kind}, BRDF)", *noise, error.describe()]),
    )
