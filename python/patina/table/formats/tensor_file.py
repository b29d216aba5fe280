"""The `tensor_file` v1.0 container of the RGL material database (.bsdf files).

Layout (little endian), as Mitsuba's TensorFile and rgl-epfl/brdf-loader read it:

    12 bytes   "tensor_file\\0"
    2 bytes    version major, minor (1, 0)
    uint32     field count
    per field: uint16 name length, name (UTF-8), uint16 rank, uint8 dtype,
               uint64 offset of the data in the file, rank x uint64 shape
    the fields' data, C order, at their offsets

dtype codes: 1 uint8, 2 int8, 3 uint16, 4 int16, 5 uint32, 6 int32, 7 uint64, 8 int64,
9 float16, 10 float32, 11 float64 (0 is invalid). Every declared size is checked against
the bytes present before anything is allocated, so a damaged header costs no memory.
"""

from __future__ import annotations

import math
import os
import struct
from dataclasses import dataclass

import numpy as np

from patina.atomic import atomic_output
from patina.errors import FormatError
from patina.table.formats.whole_file import read_whole_file

MAGIC = b"tensor_file\x00"
VERSION = (1, 0)
DTYPES = {
    1: np.dtype("<u1"),
    2: np.dtype("<i1"),
    3: np.dtype("<u2"),
    4: np.dtype("<i2"),
    5: np.dtype("<u4"),
    6: np.dtype("<i4"),
    7: np.dtype("<u8"),
    8: np.dtype("<i8"),
    9: np.dtype("<f2"),
    10: np.dtype("<f4"),
    11: np.dtype("<f8"),
}
CODES = {dtype: code for code, dtype in DTYPES.items()}
MAX_FILE_BYTES = 1 << 30  # the largest RGL spectral files are ~100 MB
MAX_RANK = 16
_FIELD_HEADER = 2 + 2 + 1 + 8  # name length, rank, dtype, offset (a name and the shape follow)


@dataclass
class Field:
    name: str
    dtype: np.dtype
    offset: int
    shape: tuple[int, ...]
    header_at: int  # byte of the field's entry in the table, for messages


class TensorFile:
    """The fields of a tensor file; `array(name)` reads one (a copy, native byte order)."""

    def __init__(self, path: str, raw: bytes, fields: dict[str, Field]) -> None:
        self.path = path
        self.raw = raw
        self.fields = fields

    def array(self, name: str) -> np.ndarray:
        f = self.fields[name]
        count = math.prod(f.shape)
        return np.frombuffer(self.raw, dtype=f.dtype, count=count, offset=f.offset).reshape(f.shape).copy()

    def fail(self, name: str, problem: str) -> FormatError:
        where = f"field '{name}' at byte {self.fields[name].header_at}" if name in self.fields else f"field '{name}'"
        return FormatError(self.path, where, problem)


def read_tensor_file(path: str | os.PathLike[str]) -> TensorFile:
    name = os.fspath(path)
    raw = read_whole_file(name, MAX_FILE_BYTES)
    return parse_tensor_file(name, raw)


def parse_tensor_file(name: str, raw: bytes) -> TensorFile:
    size = len(raw)
    if size < 18:
        raise FormatError(name, "byte 0", f"{size} bytes: too short for a tensor_file header (18 bytes)")
    if raw[:12] != MAGIC:
        raise FormatError(name, "byte 0", f"magic {raw[:12]!r}: expected {MAGIC!r} (an RGL tensor file)")
    if (raw[12], raw[13]) != VERSION:
        raise FormatError(name, "byte 12", f"version {raw[12]}.{raw[13]}: only tensor_file 1.0 is read")
    (count,) = struct.unpack_from("<I", raw, 14)
    if count == 0:
        raise FormatError(name, "byte 14", "the field table is empty")
    if count * _FIELD_HEADER > size - 18:
        raise FormatError(name, "byte 14", f"{count} fields declared: more than the {size} bytes can hold")
    at = 18
    fields: dict[str, Field] = {}
    for index in range(count):
        start = at
        if at + 2 > size:
            raise FormatError(name, f"byte {at}", f"truncated in the field table (field {index + 1} of {count})")
        (length,) = struct.unpack_from("<H", raw, at)
        at += 2
        if at + length + _FIELD_HEADER - 2 > size:
            raise FormatError(name, f"byte {start}", f"truncated in the field table (field {index + 1} of {count})")
        try:
            field_name = raw[at : at + length].decode("utf-8")
        except UnicodeDecodeError:
            raise FormatError(name, f"byte {at}", f"field {index + 1}'s name is not UTF-8") from None
        at += length
        rank, code, offset = struct.unpack_from("<HBQ", raw, at)
        at += 11
        where = f"field '{field_name}' at byte {start}"
        if code not in DTYPES:
            raise FormatError(name, where, f"dtype code {code}: expected 1-11 (uint8 ... float64)")
        if rank > MAX_RANK:
            raise FormatError(name, where, f"rank {rank}: more than {MAX_RANK} dimensions")
        if at + 8 * rank > size:
            raise FormatError(name, where, "truncated in its shape")
        shape = struct.unpack_from(f"<{rank}Q", raw, at)
        at += 8 * rank
        nbytes = math.prod(shape) * DTYPES[code].itemsize
        extent = math.prod(max(n, 1) for n in shape) * DTYPES[code].itemsize  # a 0 must not hide a huge one
        if offset > size or max(nbytes, extent if 0 in shape else 0) > size - offset:
            raise FormatError(
                name,
                where,
                f"shape {list(shape)} of {DTYPES[code].name} at offset {offset} needs {nbytes} bytes "
                f"but the file has {max(size - offset, 0)} from there",
            )
        if field_name in fields:
            raise FormatError(name, where, "a second field of this name")
        fields[field_name] = Field(field_name, DTYPES[code], int(offset), tuple(int(s) for s in shape), start)
    return TensorFile(name, raw, fields)


def tensor_file_bytes(arrays: dict[str, np.ndarray]) -> bytes:
    """A tensor_file holding `arrays` (each stored in its own little-endian dtype)."""
    prepared = {}
    for key, value in arrays.items():
        a = np.asarray(value)
        dtype = a.dtype.newbyteorder("<") if a.dtype.byteorder not in ("|", "<") else a.dtype
        if np.dtype(dtype.str) not in CODES:
            raise ValueError(f"field '{key}': dtype {a.dtype} has no tensor_file code")
        prepared[key] = np.ascontiguousarray(a, dtype=dtype)
    header = bytearray(MAGIC + bytes(VERSION) + struct.pack("<I", len(prepared)))
    entries = [(k.encode("utf-8"), a) for k, a in prepared.items()]
    header_size = len(header) + sum(2 + len(k) + 11 + 8 * a.ndim for k, a in entries)
    cursor = header_size
    body = bytearray()
    for key, a in entries:
        pad = (-cursor) % 8  # each field 8-byte aligned, as Mitsuba's numpy writer does
        body += b"\x00" * pad
        cursor += pad
        header += struct.pack("<H", len(key)) + key + struct.pack("<HBQ", a.ndim, CODES[np.dtype(a.dtype.str)], cursor)
        header += struct.pack(f"<{a.ndim}Q", *a.shape)
        body += a.tobytes()
        cursor += a.nbytes
    return bytes(header) + bytes(body)


def write_tensor_file(path: str | os.PathLike[str], arrays: dict[str, np.ndarray]) -> None:
    """Writes `arrays` as a tensor_file, atomically (a temporary file, then a rename)."""
    data = tensor_file_bytes(arrays)

    def write(tmp: str) -> None:
        with open(tmp, "wb") as out:
            out.write(data)

    atomic_output(path, write)
