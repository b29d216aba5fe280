"""patina.render.images: EXR/HDR reading with limits and clear errors, layered EXR and PNG writing, tone mapping."""

from __future__ import annotations

import os
import struct
import tempfile

import colour
import numpy as np
import OpenImageIO as oiio
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patina import atomic
from patina.errors import FormatError
from patina.render import images

RNG = np.random.default_rng(7)


def write_raw(path: str, pixels: np.ndarray, names: tuple[str, ...], fmt=oiio.FLOAT, compression: str = "zip") -> None:
    """Any pixels (NaN included) straight through OpenImageIO, bypassing write_exr's checks."""
    height, width, channels = pixels.shape
    spec = oiio.ImageSpec(width, height, channels, fmt)
    spec.channelnames = names
    spec.attribute("compression", compression)
    out = oiio.ImageOutput.create(path)
    assert out.open(path, spec) and out.write_image(np.ascontiguousarray(pixels, dtype=np.float32))
    out.close()


def sample_layers(height: int = 5, width: int = 7) -> dict[str, np.ndarray]:
    return {
        "beauty": RNG.random((height, width, 3)).astype(np.float32) * 10.0,
        "albedo": RNG.random((height, width, 3)).astype(np.float32),
        "normal": RNG.uniform(-1.0, 1.0, (height, width, 3)).astype(np.float32),
        "depth": RNG.random((height, width)).astype(np.float32) * 100.0,
        "illuminance": RNG.random((height, width)).astype(np.float32) * 1e5,
    }


# ---------------------------------------------------------------- EXR round trips


def test_exr_layers_round_trip_float(tmp_path):
    layers = sample_layers()
    path = tmp_path / "render.exr"
    images.write_exr(path, layers, {"patina:scene": "scene.json", "patina:spp": 64})
    back, _ = images.read_exr_layers(path)
    assert set(back) == set(layers)
    for name, array in layers.items():
        assert back[name].shape == array.shape
        assert np.array_equal(back[name], array), name
    assert np.array_equal(images.read_image(path), layers["beauty"])


def test_exr_channel_names_follow_the_documented_mapping(tmp_path):
    path = tmp_path / "render.exr"
    images.write_exr(path, sample_layers())
    inp = oiio.ImageInput.open(str(path))
    spec = inp.spec()
    inp.close()
    assert set(spec.channelnames) == {
        "R",
        "G",
        "B",
        "albedo.R",
        "albedo.G",
        "albedo.B",
        "normal.X",
        "normal.Y",
        "normal.Z",
        "depth.Z",
        "illuminance.Y",
    }
    assert spec.format == oiio.FLOAT
    assert spec.get_string_attribute("compression") == "zip"


def test_exr_half_round_trip_and_range(tmp_path):
    layers = sample_layers()
    path = tmp_path / "half.exr"
    images.write_exr(path, layers, half=True)
    back, _ = images.read_exr_layers(path)
    for name, array in layers.items():
        stored = array if name in images.FLOAT_LAYERS else array.astype(np.float16).astype(np.float32)
        assert np.array_equal(back[name], stored), name
    inp = oiio.ImageInput.open(str(path))
    formats = dict(zip(inp.spec().channelnames, inp.spec().channelformats))
    inp.close()
    assert formats["R"] == oiio.HALF and formats["illuminance.Y"] == oiio.FLOAT and formats["depth.Z"] == oiio.FLOAT
    with pytest.raises(ValueError, match="half range"):
        images.write_exr(path, {"beauty": np.full((2, 2, 3), 1e5)}, half=True)


def test_exr_metadata_round_trip(tmp_path):
    metadata = {
        "patina:scene": "scenes/preview.json",
        "patina:spp": 256,
        "patina:seconds": 12.5,
        "patina:version": "0.1",
    }
    path = tmp_path / "meta.exr"
    images.write_exr(path, {"beauty": np.ones((2, 3, 3))}, metadata)
    _, back = images.read_exr_layers(path)
    assert {k: back[k] for k in metadata} == metadata
    assert "DateTime" not in back  # no time stamp: the same render gives the same file


def test_exr_writer_rejects_bad_layers(tmp_path):
    path = tmp_path / "bad.exr"
    with pytest.raises(ValueError, match="NaN"):
        images.write_exr(path, {"beauty": np.full((2, 2, 3), np.nan)})
    with pytest.raises(ValueError, match="first layer"):
        images.write_exr(path, {"beauty": np.ones((2, 2, 3)), "depth": np.ones((3, 2))})
    with pytest.raises(ValueError, match="cannot be named"):
        images.write_exr(path, {"normal": np.ones((2, 2, 2))})
    with pytest.raises(ValueError, match="metadata"):
        images.write_exr(path, {"beauty": np.ones((2, 2, 3))}, {"patina:list": [1, 2]})
    assert not os.listdir(tmp_path)


# ---------------------------------------------------------------- reading other layouts


def test_read_grey_and_alpha_and_hdr(tmp_path):
    grey = RNG.random((4, 5, 1)).astype(np.float32)
    write_raw(str(tmp_path / "grey.exr"), grey, ("Y",))
    assert np.array_equal(images.read_image(tmp_path / "grey.exr"), np.repeat(grey, 3, axis=2))

    rgba = RNG.random((4, 5, 4)).astype(np.float32)
    write_raw(str(tmp_path / "rgba.exr"), rgba, ("R", "G", "B", "A"))
    assert np.array_equal(images.read_image(tmp_path / "rgba.exr"), rgba[..., :3])

    rgb = RNG.uniform(0.01, 50.0, (6, 16, 3)).astype(np.float32)
    write_raw(str(tmp_path / "map.hdr"), rgb, ("R", "G", "B"), compression="")
    back = images.read_image(tmp_path / "map.hdr")
    assert back.dtype == np.float32 and back.shape == rgb.shape
    # RGBE keeps 8 mantissa bits shared by the three channels: < 1% of the largest
    assert np.all(np.abs(back - rgb) <= 0.01 * rgb.max(axis=2, keepdims=True))


def test_nan_and_inf_pixels_are_reported(tmp_path):
    pixels = np.ones((4, 6, 3), dtype=np.float32)
    pixels[2, 3, 1] = np.nan
    pixels[3, 5, 0] = np.inf
    path = str(tmp_path / "nan.exr")
    write_raw(path, pixels, ("R", "G", "B"))
    with pytest.raises(FormatError) as caught:
        images.read_image(path)
    assert caught.value.where == "pixel x=3 y=2 channel G"
    assert "2 non-finite values" in caught.value.problem
    with pytest.raises(FormatError, match="not finite"):
        images.read_exr_layers(path)


@pytest.mark.parametrize(
    ("name", "content", "message"),
    [
        ("empty.exr", b"", "not an OpenEXR or Radiance HDR"),
        ("text.exr", b"hello world, not an image", "not an OpenEXR or Radiance HDR"),
        ("picture.png", b"\x89PNG\r\n\x1a\n", "extension '.png'"),
        ("noext", b"\x76\x2f\x31\x01", "extension"),
        ("exr-inside.hdr", b"\x76\x2f\x31\x01\x02\x00\x00\x00", "content is openexr"),
        ("hdr-inside.exr", b"#?RADIANCE\n", "content is hdr"),
        ("header-only.exr", b"\x76\x2f\x31\x01\x02\x00\x00\x00", "header"),
        ("header-only.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n", "header"),
    ],
)
def test_unreadable_files_raise_format_error(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(FormatError, match=message) as caught:
        images.read_image(path)
    assert caught.value.path == str(path)


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(FormatError, match="no such file"):
        images.read_image(tmp_path / "absent.exr")
    (tmp_path / "dir.exr").mkdir()
    with pytest.raises(FormatError, match="not a regular file"):
        images.read_image(tmp_path / "dir.exr")


def test_truncated_exr_raises_format_error(tmp_path):
    path = tmp_path / "full.exr"
    images.write_exr(path, {"beauty": RNG.random((64, 64, 3))})
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(FormatError) as caught:
        images.read_image(path)
    assert caught.value.where in ("header", "pixel data")


# ---------------------------------------------------------------- declared size checks


def test_oversized_declared_size_is_rejected_before_pixels_are_read(tmp_path, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("pixels were read")

    monkeypatch.setattr(images, "_read_channels", never)
    path = tmp_path / "small.exr"
    images.write_exr(path, {"beauty": np.ones((16, 16, 3))})
    with pytest.raises(FormatError, match="16 x 16 = 256 pixels exceeds the limit of 100") as caught:
        images.read_image(path, max_pixels=100)
    assert caught.value.where == "header"


def test_crafted_huge_hdr_header_is_rejected(tmp_path, monkeypatch):
    monkeypatch.setattr(images, "_read_channels", lambda *a: pytest.fail("pixels were read"))
    path = tmp_path / "huge.hdr"
    path.write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 60000 +X 60000\n" + b"\x02\x02\x00\x10" * 8)
    with pytest.raises(FormatError) as caught:
        images.read_image(path)
    assert caught.value.where == "header"
    assert "60000" in caught.value.problem


def test_crafted_huge_exr_data_window_is_rejected(tmp_path, monkeypatch):
    monkeypatch.setattr(images, "_read_channels", lambda *a: pytest.fail("pixels were read"))
    path = tmp_path / "huge.exr"
    images.write_exr(path, {"beauty": np.ones((4, 4, 3))})
    data = bytearray(path.read_bytes())
    tag = b"dataWindow\x00box2i\x00"
    at = data.index(tag) + len(tag) + 4  # past the attribute's byte size
    data[at : at + 16] = struct.pack("<4i", 0, 0, 59999, 59999)
    path.write_bytes(bytes(data))
    with pytest.raises(FormatError) as caught:
        images.read_image(path)
    assert caught.value.where == "header"


# ---------------------------------------------------------------- fuzzing


def _valid_bytes(suffix: str) -> bytes:
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "seed" + suffix)
        pixels = np.random.default_rng(3).uniform(0.0, 4.0, (6, 16, 3)).astype(np.float32)
        write_raw(path, pixels, ("R", "G", "B"), compression="zip" if suffix == ".exr" else "")
        with open(path, "rb") as f:
            return f.read()


SEEDS = {suffix: _valid_bytes(suffix) for suffix in (".exr", ".hdr")}
FUZZ_DIR = tempfile.mkdtemp(prefix="patina-images-fuzz-")

mutations = st.lists(st.tuples(st.integers(min_value=0, max_value=10_000), st.integers(0, 255)), max_size=8)


def _check_read(suffix: str, data: bytes) -> None:
    path = os.path.join(FUZZ_DIR, "fuzz" + suffix)
    with open(path, "wb") as f:
        f.write(data)
    try:
        rgb = images.read_image(path, max_pixels=1_000_000)
    except FormatError as e:
        assert e.path == path and e.problem
    else:
        assert rgb.dtype == np.float32 and rgb.ndim == 3 and rgb.shape[2] == 3
        assert np.isfinite(rgb).all()


@pytest.mark.parametrize("suffix", [".exr", ".hdr"])
@settings(max_examples=150, deadline=None)
@given(keep=st.floats(min_value=0.0, max_value=1.0), truncate=st.booleans(), changes=mutations)
def test_fuzzed_files_never_crash(suffix, keep, truncate, changes):
    data = bytearray(SEEDS[suffix])
    for position, value in changes:
        data[position % len(data)] = value
    _check_read(suffix, bytes(data[: int(keep * len(data))] if truncate else data))


@pytest.mark.parametrize("suffix", [".exr", ".hdr"])
@settings(max_examples=100, deadline=None)
@given(tail=st.binary(max_size=600))
def test_random_bytes_after_the_magic_never_crash(suffix, tail):
    magic = images.EXR_MAGIC if suffix == ".exr" else b"#?RADIANCE\n"
    _check_read(suffix, magic + tail)


# ---------------------------------------------------------------- tone mapping and PNG


def test_srgb_encoding_matches_colour_science():
    x = np.concatenate([np.linspace(0.0, 1.0, 1001), [0.0031308, 0.00313, 0.0032]])
    assert np.allclose(images.srgb_encode(x), colour.cctf_encoding(x, function="sRGB"), atol=1e-12)


def test_tonemap_known_values():
    rgb = np.array([[[0.0, 1.0, 0.5], [2.0, -1.0, np.nan], [np.inf, -np.inf, 0.0031308]]])
    out = images.tonemap(rgb, curve="clamp")
    assert out.dtype == np.uint8 and out.shape == (1, 3, 3)
    assert out.tolist() == [[[0, 255, 188], [255, 0, 0], [255, 0, 10]]]
    # one stop up doubles: 0.25 shows as 0.5 does
    assert images.tonemap(np.full((1, 1, 3), 0.25), exposure_stops=1.0)[0, 0, 0] == 188
    assert images.tonemap(np.full((2, 2), 0.5)).shape == (2, 2, 3)


def test_filmic_curve():
    assert images.aces_fitted(1.0) == pytest.approx(2.54 / 3.16)
    assert images.aces_fitted(0.0) == 0.0
    x = np.linspace(0.0, 100.0, 10_001)
    y = images.aces_fitted(x)
    assert np.all(np.diff(y) >= 0.0) and y[-1] == 1.0
    out = images.tonemap(np.array([[[0.0, 1.0, 1e6]]]), curve="filmic")
    assert out.tolist() == [[[0, round(255 * float(images.srgb_encode(2.54 / 3.16))), 255]]]


def test_tonemap_rejects_bad_arguments():
    with pytest.raises(ValueError, match="curve"):
        images.tonemap(np.ones((2, 2, 3)), curve="reinhard")
    with pytest.raises(ValueError, match="shape"):
        images.tonemap(np.ones((2, 2, 5)))


def test_png_values(tmp_path):
    rgb = np.array([[[0.0, 0.5, 1.0], [0.2, 0.04, 3.0]]])
    path = tmp_path / "out.png"
    images.write_png(path, rgb, curve="clamp")
    inp = oiio.ImageInput.open(str(path))
    back = inp.read_image(oiio.UINT8)
    inp.close()
    assert back.tolist() == images.tonemap(rgb, curve="clamp").tolist()
    assert back[0, 0].tolist() == [0, 188, 255]
    assert os.listdir(tmp_path) == ["out.png"]
    assert os.stat(path).st_mode & 0o777 == atomic.NEW_FILE_MODE


# ---------------------------------------------------------------- atomic writes


def test_failed_write_keeps_the_existing_file_and_leaves_no_temporary(tmp_path, monkeypatch):
    path = tmp_path / "render.exr"
    images.write_exr(path, {"beauty": np.ones((3, 3, 3))})
    before = path.read_bytes()

    def half_written(tmp, spec, pixels):
        with open(tmp, "wb") as f:
            f.write(b"\x76\x2f\x31\x01 partial")
        raise OSError("disk full")

    monkeypatch.setattr(images, "_write_oiio", half_written)
    with pytest.raises(OSError, match="disk full"):
        images.write_exr(path, {"beauty": np.zeros((3, 3, 3))})
    with pytest.raises(OSError, match="disk full"):
        images.write_png(tmp_path / "render.png", np.zeros((3, 3, 3)))
    assert path.read_bytes() == before
    assert os.listdir(tmp_path) == ["render.exr"]


def test_successful_write_replaces_and_leaves_no_temporary(tmp_path):
    path = tmp_path / "render.exr"
    images.write_exr(path, {"beauty": np.ones((3, 3, 3))})
    images.write_exr(path, {"beauty": np.full((3, 3, 3), 2.0)})
    assert os.listdir(tmp_path) == ["render.exr"]
    assert np.all(images.read_image(path) == 2.0)
