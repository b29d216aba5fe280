"""Image input and output through OpenImageIO: HDR inputs, EXR renders with AOVs, tone-mapped PNG.

Inputs are only OpenEXR and Radiance HDR, recognised by both extension and magic bytes,
with OpenImageIO's own limits set and the header's declared size checked before any
pixel is read; every failure is a `FormatError` naming the file, the place and the problem.

EXR channel naming (`write_exr` / `read_exr_layers`): the layer called "beauty" is
written as the unprefixed channels R, G, B (A if it has four channels); any other layer
L becomes channels "L.<c>", the suffixes c from `CHANNEL_SUFFIXES` for the known AOVs
(normal and position: X Y Z, depth: Z, illuminance: Y) and otherwise from the channel
count (1: Y, 2: X Y, 3: R G B, 4: R G B A). An (H, W) array is one channel.

Outputs are written to a temporary file beside the target, then renamed over it, so a
failed write leaves neither a half-written file nor a damaged earlier one.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import OpenImageIO as oiio

from patina.atomic import atomic_output
from patina.errors import FormatError
from patina.file_names import printable

EXR_MAGIC = b"\x76\x2f\x31\x01"
HDR_MAGICS = (b"#?RADIANCE", b"#?RGBE")
EXTENSIONS = {".exr": "openexr", ".hdr": "hdr", ".rgbe": "hdr"}
MAX_CHANNELS = 64  # far more than any render's AOVs; more is a corrupt or hostile header
MAX_DIMENSION = 1 << 16  # per side
# OpenImageIO's byte limit allows this many float channels at the full pixel limit
_LIMIT_CHANNELS_AT_MAX_PIXELS = 16

CHANNEL_SUFFIXES: dict[str, tuple[str, ...]] = {
    "normal": ("X", "Y", "Z"),
    "position": ("X", "Y", "Z"),
    "depth": ("Z",),
    "illuminance": ("Y",),
}
# layers kept float32 when writing half: lux and distances exceed half's range or precision
FLOAT_LAYERS = frozenset({"depth", "position", "illuminance"})
HALF_MAX = 65504.0
MAX_EXPOSURE_STOPS = 64.0  # 2^64: far past any real image, and 2^exposure stays finite
_SUFFIXES_BY_COUNT = {1: ("Y",), 2: ("X", "Y"), 3: ("R", "G", "B"), 4: ("R", "G", "B", "A")}
# canonical order of channels inside a layer (EXR stores them alphabetically)
_CHANNEL_ORDER = ("R", "G", "B", "A", "X", "Y", "Z", "U", "V", "W")
_INTERNAL_ATTRIBUTES = ("oiio:", "openexr:", "PixelAspectRatio", "screenWindow")


# ---------------------------------------------------------------- reading


def _oiio_problem(fallback: str, source: oiio.ImageInput | oiio.ImageOutput | None = None) -> str:
    """OpenImageIO's pending error message (of `source`, else global) on one line, or `fallback`."""
    try:
        message = source.geterror() if source is not None else ""
        message = message or oiio.geterror()
    except UnicodeDecodeError:
        # the message quotes bytes of a corrupt file that are not UTF-8 (and is now cleared)
        return f"{fallback} (OpenImageIO's message was not valid text)"
    # OpenImageIO's advice to raise its limits is not for our users
    lines = [line.strip() for line in message.splitlines() if line.strip() and not line.startswith("If ")]
    return " ".join(lines) if lines else fallback


def _detect_format(path: Path) -> str:
    """Plugin name from the extension, after checking the magic bytes agree with it."""
    kind = EXTENSIONS.get(path.suffix.lower())
    if kind is None:
        raise FormatError(str(path), "file name", f"extension {path.suffix or '(none)'!r} is not .exr or .hdr")
    try:
        with open(path, "rb") as f:
            head = f.read(16)
    except OSError as e:
        raise FormatError(str(path), "", f"cannot open: {e.strerror or e}") from None
    if head.startswith(EXR_MAGIC):
        found = "openexr"
    elif head.startswith(HDR_MAGICS):
        found = "hdr"
    else:
        raise FormatError(str(path), "byte 0", f"not an OpenEXR or Radiance HDR file (starts with {head[:10]!r})")
    if found != kind:
        raise FormatError(str(path), "byte 0", f"extension {path.suffix!r} but the content is {found}")
    return kind


def _open(path: str | os.PathLike, max_pixels: int) -> tuple[Path, oiio.ImageInput, oiio.ImageSpec]:
    """Open an EXR/HDR file and check its declared size; pixels are not read yet."""
    path = Path(path)
    if not path.is_file():
        raise FormatError(str(path), "", "no such file" if not path.exists() else "not a regular file")
    _detect_format(path)
    oiio.attribute("limits:channels", MAX_CHANNELS)
    oiio.attribute("limits:resolution", MAX_DIMENSION)
    budget = max_pixels * _LIMIT_CHANNELS_AT_MAX_PIXELS * 4
    oiio.attribute("limits:imagesize_MB", max(1, math.ceil(budget / 2**20)))
    _oiio_problem("")  # drop any stale message so the one reported is this file's
    inp = oiio.ImageInput.open(str(path))
    if inp is None:
        raise FormatError(str(path), "header", _oiio_problem("OpenImageIO could not open it"))
    spec = inp.spec()
    width, height, depth, nchannels = spec.width, spec.height, spec.depth, spec.nchannels
    problem = ""
    if width <= 0 or height <= 0 or depth != 1:
        problem = f"declared size {width} x {height} x {depth} is empty or not a 2-D image"
    elif width * height > max_pixels:
        problem = f"declared size {width} x {height} = {width * height} pixels exceeds the limit of {max_pixels}"
    elif not 1 <= nchannels <= MAX_CHANNELS:
        problem = f"declared {nchannels} channels (1 to {MAX_CHANNELS} allowed)"
    elif spec.deep:
        problem = "deep (multi-sample) images are not supported"
    if problem:
        inp.close()
        raise FormatError(str(path), "header", problem)
    return path, inp, spec


def _read_channels(path: Path, inp: oiio.ImageInput, spec: oiio.ImageSpec, first: int, last: int) -> np.ndarray:
    """Pixels of channels [first, last) as float32 (H, W, C); closes `inp`."""
    try:
        pixels = inp.read_image(0, 0, first, last, oiio.FLOAT)
        problem = _oiio_problem("pixel data could not be read", inp) if pixels is None else ""
    finally:
        inp.close()
    shape = (spec.height, spec.width, last - first)
    if not problem and np.size(pixels) != math.prod(shape):
        problem = f"OpenImageIO returned {np.size(pixels)} values for {shape}"
    if problem:
        raise FormatError(str(path), "pixel data", problem)
    return np.asarray(pixels, dtype=np.float32).reshape(shape)


def _check_finite(path: Path, pixels: np.ndarray, names: list[str]) -> None:
    bad = ~np.isfinite(pixels)
    if bad.any():
        y, x, c = np.argwhere(bad)[0]
        count = int(bad.sum())
        raise FormatError(
            str(path),
            f"pixel x={x} y={y} channel {names[c]}",
            f"value {pixels[y, x, c]} is not finite ({count} non-finite value{'s' if count > 1 else ''} in all)",
        )


def read_image(path: str | os.PathLike, max_pixels: int = 64_000_000) -> np.ndarray:
    """A linear RGB image (H, W, 3) float32 from an OpenEXR or Radiance HDR file.

    R, G, B are taken by name (else a Y or single channel is replicated to grey, else
    the first three channels); alpha and other channels are dropped. Raises FormatError
    for a missing, unrecognised, truncated or corrupt file, a declared size over
    `max_pixels`, or any NaN/Inf pixel (the first one is named).
    """
    path, inp, spec = _open(path, max_pixels)
    names = list(spec.channelnames)
    if all(c in names for c in "RGB"):
        picks = [names.index(c) for c in "RGB"]
    elif "Y" in names:
        picks = [names.index("Y")] * 3
    elif len(names) >= 3:
        picks = [0, 1, 2]
    else:
        picks = [0] * 3
    first, last = min(picks), max(picks) + 1
    pixels = _read_channels(path, inp, spec, first, last)
    rgb = np.ascontiguousarray(pixels[..., [p - first for p in picks]])
    _check_finite(path, rgb, [names[p] for p in picks])
    return rgb


def _split_channel(name: str) -> tuple[str, str]:
    layer, dot, suffix = name.rpartition(".")
    return (layer, suffix) if dot else ("beauty", name)


def read_exr_layers(
    path: str | os.PathLike, max_pixels: int = 64_000_000
) -> tuple[dict[str, np.ndarray], dict[str, str | float | int]]:
    """All layers of an EXR written by `write_exr` (the module docstring gives the naming) and
    its header metadata. One-channel layers come back (H, W), others (H, W, C) float32, the
    channels in R G B A / X Y Z order. Same checks as `read_image`."""
    path, inp, spec = _open(path, max_pixels)
    if path.suffix.lower() != ".exr":
        inp.close()
        raise FormatError(str(path), "file name", "layers are read from OpenEXR files only")
    names = list(spec.channelnames)
    metadata = _metadata_from_spec(spec)
    pixels = _read_channels(path, inp, spec, 0, len(names))
    _check_finite(path, pixels, names)
    grouped: dict[str, list[tuple[str, int]]] = {}
    for index, name in enumerate(names):
        layer, suffix = _split_channel(name)
        grouped.setdefault(layer, []).append((suffix, index))

    def order(item: tuple[str, int]) -> tuple[int, str]:
        suffix = item[0]
        return (_CHANNEL_ORDER.index(suffix) if suffix in _CHANNEL_ORDER else len(_CHANNEL_ORDER), suffix)

    layers = {}
    for layer, channels in grouped.items():
        indices = [index for _, index in sorted(channels, key=order)]
        array = np.ascontiguousarray(pixels[..., indices])
        layers[layer] = array[..., 0] if len(indices) == 1 else array
    return layers, metadata


def _metadata_from_spec(spec: oiio.ImageSpec) -> dict[str, str | float | int]:
    metadata: dict[str, str | float | int] = {}
    for attribute in spec.extra_attribs:
        if attribute.name.startswith(_INTERNAL_ATTRIBUTES) or attribute.name == "compression":
            continue
        if isinstance(attribute.value, (str, int, float)):
            metadata[attribute.name] = attribute.value
    return metadata


# ---------------------------------------------------------------- writing


def _encode_oiio(name: str, spec: oiio.ImageSpec, pixels: np.ndarray) -> bytes:
    """The file OpenImageIO writes for `pixels`, as bytes: encoded into an anonymous memory
    file, never onto the output's disk. There a full disk is not reported by every codec:
    libpng's writes left a truncated PNG and success, libjpeg's ended the whole process
    (exit 1, in the library). `name`: the output's name, whose extension picks the format."""
    out = oiio.ImageOutput.create("image" + printable(os.path.splitext(name)[1]))  # a name OIIO's str takes
    if out is None:
        raise OSError(f"{name}: {_oiio_problem('OpenImageIO has no writer for this file')}")
    fd = os.memfd_create("patina-image")
    try:  # the messages name `name`; atomic_output puts the user's path in its place
        written = out.open(f"/proc/self/fd/{fd}", spec) and out.write_image(pixels)
        closed = out.close()  # the codec's last bytes: a failure here is a failed write too
        if not (written and closed):
            raise OSError(f"{name}: {_oiio_problem('write failed', out)}")
        size = os.fstat(fd).st_size
        data = os.pread(fd, size, 0)
    finally:
        os.close(fd)
    if len(data) != size or size == 0:
        raise OSError(f"{name}: OpenImageIO wrote {size} bytes, {len(data)} read back")
    return data


def _write_oiio(tmp: str, spec: oiio.ImageSpec, pixels: np.ndarray) -> None:
    """`pixels` encoded in memory (`_encode_oiio`), then written to `tmp` by Python, whose
    writes report a full disk (atomic_output then removes `tmp` and names the output)."""
    data = _encode_oiio(tmp, spec, pixels)
    with open(tmp, "wb") as f:
        f.write(data)


def _layer_channels(name: str, array: np.ndarray) -> tuple[list[str], np.ndarray]:
    if array.ndim == 2:
        array = array[..., None]
    if array.ndim != 3:
        raise ValueError(f"layer {name!r}: expected an (H, W) or (H, W, C) array, got shape {array.shape}")
    count = array.shape[2]
    suffixes = CHANNEL_SUFFIXES.get(name) or _SUFFIXES_BY_COUNT.get(count)
    if suffixes is None or len(suffixes) != count:
        raise ValueError(f"layer {name!r}: {count} channels cannot be named (expected {len(suffixes or ())})")
    if name == "beauty":
        return list(suffixes), array
    if not name or "." in name:
        raise ValueError(f"layer name {name!r} must be non-empty and contain no '.'")
    return [f"{name}.{s}" for s in suffixes], array


INT32_RANGE = (-(2**31), 2**31 - 1)
FLOAT32_MAX = float(np.finfo(np.float32).max)


def _exr_attribute(value: str | float | int) -> str | float | int:
    """A metadata value as an EXR attribute can hold it: EXR ints and floats are 32-bit, so an
    int beyond int32 or a float beyond float32 (or not finite) is written as its decimal text
    rather than failing (or turning into inf) after a render is done."""
    if isinstance(value, int) and not INT32_RANGE[0] <= value <= INT32_RANGE[1]:
        return str(value)
    if isinstance(value, float) and not (math.isfinite(value) and abs(value) <= FLOAT32_MAX):
        return repr(value)
    return value


def write_exr(
    path: str | os.PathLike,
    layers: Mapping[str, np.ndarray],
    metadata: Mapping[str, str | float | int] | None = None,
    *,
    half: bool = False,
) -> None:
    """Write the layers as one ZIP-compressed multi-channel EXR, float32 (or half), atomically.

    With `half`, every layer but those in FLOAT_LAYERS is stored as half float.

    `layers` maps a layer name to an (H, W) or (H, W, C) array, all the same H and W;
    "beauty" becomes R, G, B, others "name.<suffix>" (module docstring). `metadata` values
    (str, int, float) become header attributes, e.g. "patina:spp"; ints beyond 32 bits and
    floats beyond float32 are written as decimal strings (`_exr_attribute`). Raises ValueError for
    mismatched shapes, unnamed channels, NaN/Inf values and half layers beyond half range.
    """
    if not layers:
        raise ValueError("no layers to write")
    names: list[str] = []
    formats: list[oiio.TypeDesc] = []
    shaped_layers: list[tuple[str, np.ndarray]] = []
    shape = None
    for name, given in layers.items():
        channels, shaped = _layer_channels(name, np.asarray(given))
        if shape is None:
            shape = shaped.shape[:2]
        elif shaped.shape[:2] != shape:
            raise ValueError(f"layer {name!r} is {shaped.shape[:2]}, the first layer {shape}")
        layer_half = half and name not in FLOAT_LAYERS
        names.extend(channels)
        formats.extend([oiio.HALF if layer_half else oiio.FLOAT] * len(channels))
        shaped_layers.append((name, shaped))
    assert shape is not None
    # one float32 buffer filled layer by layer: a large render's copy of its images, once
    pixels = np.empty((*shape, len(names)), np.float32)
    first = 0
    for name, shaped in shaped_layers:
        array = pixels[..., first : first + shaped.shape[2]]
        first += shaped.shape[2]
        array[...] = shaped
        if not np.isfinite(array).all():
            raise ValueError(f"{os.fspath(path)}: layer {name!r} has NaN or Inf values")
        if half and name not in FLOAT_LAYERS and np.abs(array).max(initial=0.0) > HALF_MAX:
            raise ValueError(f"{os.fspath(path)}: layer {name!r} has values beyond half range ({HALF_MAX})")
    height, width = pixels.shape[:2]
    if height == 0 or width == 0:
        raise ValueError("the image is empty")
    spec = oiio.ImageSpec(width, height, len(names), oiio.HALF if half else oiio.FLOAT)
    spec.channelformats = tuple(formats)
    spec.channelnames = tuple(names)
    spec.attribute("compression", "zip")
    spec.attribute("DateTime", "")  # OpenImageIO would stamp the time; outputs stay reproducible
    for key, value in (metadata or {}).items():
        if isinstance(value, bool) or not isinstance(value, (str, int, float)):
            raise ValueError(f"metadata {key!r}: {type(value).__name__} is not str, int or float")
        spec.attribute(key, _exr_attribute(value))
    atomic_output(path, lambda tmp: _write_oiio(tmp, spec, pixels))


# ---------------------------------------------------------------- display


def srgb_encode(linear: np.ndarray) -> np.ndarray:
    """The sRGB OETF (IEC 61966-2-1) on values in [0, 1]."""
    linear = np.asarray(linear, dtype=np.float64)
    return np.where(
        linear <= 0.0031308, 12.92 * linear, 1.055 * np.power(np.maximum(linear, 0.0031308), 1.0 / 2.4) - 0.055
    )


def aces_fitted(x: np.ndarray) -> np.ndarray:
    """ACES filmic curve fitted by K. Narkowicz ("ACES Filmic Tone Mapping Curve", 2016):
    x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1]; applied per channel
    to the exposed linear value, without the 0.6 pre-scale some uses add."""
    x = np.asarray(x, dtype=np.float64)
    return np.clip(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0)


def tonemap(rgb: np.ndarray, exposure_stops: float = 0.0, curve: str = "clamp") -> np.ndarray:
    """8-bit sRGB (H, W, 3) of a linear image (H, W, 3) or grey (H, W): scale by 2^exposure,
    apply `curve` ("clamp" to [0, 1], or "filmic": `aces_fitted`), encode with the sRGB OETF.
    NaN and negative values show as black, +Inf as white."""
    rgb = np.asarray(rgb, dtype=np.float64)
    if rgb.ndim == 2 or (rgb.ndim == 3 and rgb.shape[2] == 1):
        rgb = np.repeat(rgb.reshape(*rgb.shape[:2], 1), 3, axis=2)
    if rgb.ndim != 3 or rgb.shape[2] != 3:
        raise ValueError(f"expected an (H, W, 3) or (H, W) image, got shape {rgb.shape}")
    if curve not in ("clamp", "filmic"):
        raise ValueError(f"curve must be 'clamp' or 'filmic', not {curve!r}")
    if not (math.isfinite(exposure_stops) and abs(exposure_stops) <= MAX_EXPOSURE_STOPS):
        raise ValueError(f"exposure must be within +-{MAX_EXPOSURE_STOPS:g} stops, not {exposure_stops:g}")
    x = np.nan_to_num(rgb * 2.0**exposure_stops, nan=0.0, posinf=1e30, neginf=0.0)
    x = np.maximum(x, 0.0)
    display = np.clip(x, 0.0, 1.0) if curve == "clamp" else aces_fitted(x)
    return np.round(255.0 * srgb_encode(display)).astype(np.uint8)


TONEMAP_ROWS = 256  # rows tone-mapped at a time: tonemap's float64 temporaries stay small


def write_png(path: str | os.PathLike, rgb: np.ndarray, exposure_stops: float = 0.0, curve: str = "filmic") -> None:
    """Tone-map (`tonemap`) and write an 8-bit sRGB PNG atomically."""
    rgb = np.asarray(rgb)
    if rgb.ndim >= 2 and rgb.shape[0] > TONEMAP_ROWS:
        pixels = np.empty((*rgb.shape[:2], 3), np.uint8)
        for r in range(0, rgb.shape[0], TONEMAP_ROWS):
            pixels[r : r + TONEMAP_ROWS] = tonemap(rgb[r : r + TONEMAP_ROWS], exposure_stops, curve)
    else:
        pixels = np.ascontiguousarray(tonemap(rgb, exposure_stops, curve))
    height, width = pixels.shape[:2]
    if height == 0 or width == 0:
        raise ValueError("the image is empty")
    spec = oiio.ImageSpec(width, height, 3, oiio.UINT8)
    spec.attribute("oiio:ColorSpace", "sRGB")
    spec.attribute("DateTime", "")
    atomic_output(path, lambda tmp: _write_oiio(tmp, spec, pixels))
