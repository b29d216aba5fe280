"""NVIDIA MDL measured BSDFs (.mbsdf), as the MDL specification's appendix on measured
BSDF data and the MDL SDK (`mi::neuraylib::IBsdf_isotropic_data`) define them:

    "NVIDIA ARC MBSDF V1\\n"
    optional metadata lines (key="value")
    one or two data blocks, each: a marker line "MBSDF_DATA_REFLECTION=\\n",
    "MBSDF_DATA_TRANSMISSION=\\n" (or "MBSDF_DATA=\\n", reflection), then uint32 type
    (0 one float, 1 three floats: RGB), uint32 res_theta, uint32 res_phi, then
    float32 values [theta_in][theta_out][phi], little endian.

The data are isotropic: theta_in and theta_out in [0, 90] degrees and phi = |phi_out -
phi_in| in [0, 180] degrees, each at the centres of res cells (texture convention: theta
(i + 0.5) * 90 / res_theta). Values are the BSDF in 1/sr, without the cosine. The
reflection block becomes an isotropic table; a file with only transmission is refused
(Patina tables are reflection).
"""

from __future__ import annotations

import struct
from typing import NoReturn

import numpy as np

from patina.errors import FormatError
from patina.table.formats.measurement_noise import checked_measurement
from patina.table.formats.tabledata import TableData
from patina.table.formats.whole_file import read_whole_file

MAGIC = b"NVIDIA ARC MBSDF V1\n"
MARKERS = {
    b"MBSDF_DATA=": "reflection",
    b"MBSDF_DATA_REFLECTION=": "reflection",
    b"MBSDF_DATA_TRANSMISSION=": "transmission",
}
TYPES = {0: ("mono", 1), 1: ("rgb", 3)}
MAX_RESOLUTION = 4096  # cells per angle
MAX_FILE_BYTES = 1 << 30
METADATA_SHOWN = 200  # characters of metadata kept in the provenance


def mdl_axes(res_theta: int, res_phi: int) -> list[np.ndarray]:
    theta = (np.arange(res_theta) + 0.5) * (np.pi / 2) / res_theta
    return [theta, theta, (np.arange(res_phi) + 0.5) * np.pi / res_phi]


def _blocks(path: str, raw: bytes) -> tuple[str, dict[str, tuple[int, int, int, int, int]]]:
    """The metadata text and {part: (type, res_theta, res_phi, data offset, marker byte)}."""
    if not raw.startswith(MAGIC):
        raise FormatError(path, "byte 0", f"expected the header {MAGIC!r} (an MDL .mbsdf file)")
    at = len(MAGIC)
    metadata: list[str] = []
    blocks: dict[str, tuple[int, int, int, int, int]] = {}
    while at < len(raw):
        end = raw.find(b"\n", at)
        line = raw[at : end if end >= 0 else len(raw)]
        if line.rstrip(b"\r") in MARKERS:
            part = MARKERS[line.rstrip(b"\r")]
            start = end + 1
            if part in blocks:
                raise FormatError(path, f"byte {at}", f"a second {part} block")
            if start + 12 > len(raw):
                raise FormatError(path, f"byte {start}", f"truncated {part} block header (type, res_theta, res_phi)")
            kind, res_theta, res_phi = struct.unpack_from("<III", raw, start)
            if kind not in TYPES:
                raise FormatError(path, f"byte {start}", f"data type {kind}: expected 0 (scalar) or 1 (RGB)")
            for name, res, at_byte in (("res_theta", res_theta, start + 4), ("res_phi", res_phi, start + 8)):
                if not 1 <= res <= MAX_RESOLUTION:
                    raise FormatError(path, f"byte {at_byte}", f"{name} {res}: expected 1 to {MAX_RESOLUTION}")
            nbytes = res_theta * res_theta * res_phi * TYPES[kind][1] * 4
            if nbytes > len(raw) - start - 12:
                raise FormatError(
                    path,
                    f"byte {start}",
                    f"{part} block of {res_theta} x {res_theta} x {res_phi} {TYPES[kind][0]} values needs "
                    f"{nbytes} bytes but the file has {len(raw) - start - 12} after its header",
                )
            blocks[part] = (kind, res_theta, res_phi, start + 12, at)
            at = start + 12 + nbytes
            continue
        if blocks:
            raise FormatError(path, f"byte {at}", "unexpected content after the data blocks")
        if end < 0:
            break
        try:
            metadata.append(line.decode("utf-8").strip())
        except UnicodeDecodeError:
            raise FormatError(path, f"byte {at}", "a metadata line that is not UTF-8 text") from None
        at = end + 1
    if not blocks:
        raise FormatError(path, "file", "no MBSDF_DATA_REFLECTION= / MBSDF_DATA_TRANSMISSION= block")
    return " ".join(m for m in metadata if m), blocks


def read_mdl(path: str) -> TableData:
    raw = read_whole_file(path, MAX_FILE_BYTES)
    metadata, blocks = _blocks(path, raw)
    if "reflection" not in blocks:
        raise FormatError(
            path, f"byte {blocks['transmission'][4]}", "only transmission data: Patina tables are reflection (BRDF)"
        )
    kind, res_theta, res_phi, offset, _ = blocks["reflection"]
    channel_kind, channels = TYPES[kind]
    count = res_theta * res_theta * res_phi * channels
    values = np.frombuffer(raw, dtype="<f4", count=count, offset=offset)

    def refuse(first: int, problem: str) -> NoReturn:
        raise FormatError(path, f"byte {offset + 4 * first}", f"reflection value {values[first]:g}: {problem}")

    values, noise = checked_measurement(values, refuse)
    notes = [f"MDL .mbsdf reflection block ({res_theta} x {res_theta} x {res_phi}, {channel_kind})"]
    if noise:
        notes.append(noise)
    if "transmission" in blocks:
        notes.append("transmission block skipped (Patina tables are reflection)")
    if metadata:
        notes.append(metadata[:METADATA_SHOWN])
    return TableData(
        parametrization="isotropic",
        axes=mdl_axes(res_theta, res_phi),
        values=values.reshape(res_theta, res_theta, res_phi, channels).astype(np.float32),
        channel_kind=channel_kind,
        provenance="; ".join(notes),
    )
