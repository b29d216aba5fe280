"""The bundled environment maps (materials/env): reproducible from tools/make_environments.py,
in the lat-long convention, with the sun where stated and a plausible irradiance."""

from __future__ import annotations

import importlib.util
import math
import os
import sys

import numpy as np
import pytest

from patina.colour_constants import LUMINOUS_EFFICACY, luminance
from patina.render import envmap, images
from repo_paths import ROOT

ENV = os.path.join(ROOT, "materials", "env")


@pytest.fixture(scope="module")
def tool():
    spec = importlib.util.spec_from_file_location(
        "make_environments", os.path.join(ROOT, "tools", "make_environments.py")
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def bundled_sky():
    return images.read_exr_layers(os.path.join(ENV, "sky.exr"))


@pytest.fixture(scope="module")
def generated_sky(tool):
    return tool.sky()


@pytest.mark.parametrize("name", ["studio", "sky"])
def test_bundled_files_are_small_and_documented(name):
    path = os.path.join(ENV, f"{name}.exr")
    assert os.path.getsize(path) < 2 * 1024 * 1024
    with open(os.path.join(ENV, f"{name}.md")) as f:
        provenance = f.read()
    assert "tools/make_environments.py" in provenance and "CC0" in provenance
    rgb = images.read_image(path)
    assert rgb.shape == (512, 1024, 3) and np.all(rgb >= 0.0)


def test_studio_regenerates_to_the_bundled_pixels(tool):
    bundled = images.read_image(os.path.join(ENV, "studio.exr"))
    generated = tool.studio().astype(np.float16).astype(np.float32)
    assert np.array_equal(bundled, generated)


def test_sky_regenerates_to_the_bundled_pixels(bundled_sky, generated_sky):
    bundled = bundled_sky[0]["beauty"]
    generated = generated_sky[0]
    assert np.allclose(bundled, generated, rtol=2.0**-13, atol=0.0)


def test_studio_soft_box_radiance_at_their_centres(tool):
    rgb = images.read_image(os.path.join(ENV, "studio.exr"))
    height, width = rgb.shape[:2]
    for box in tool.STUDIO_BOXES:
        u, v = envmap.direction_to_lat_long(tool.direction(box.azimuth, box.elevation))
        i, j = min(int(v * height), height - 1), int(u * width)
        assert rgb[i, j] == pytest.approx([box.radiance] * 3, rel=1e-3), box.name


def test_brightest_pixel_is_the_stated_sun_direction(bundled_sky):
    layers, metadata = bundled_sky
    rgb = layers["beauty"]
    stated = np.array([float(x) for x in metadata["patina:sun_direction"].split()])
    elevation = math.radians(metadata["patina:sun_elevation_deg"])
    azimuth = math.radians(metadata["patina:sun_azimuth_deg"])
    # the same direction from elevation and azimuth under the convention
    expected = np.array(
        [math.sin(azimuth) * math.cos(elevation), math.sin(elevation), -math.cos(azimuth) * math.cos(elevation)]
    )
    assert np.allclose(stated, expected, atol=1e-6)
    height, width = rgb.shape[:2]
    i, j = np.unravel_index(np.argmax(luminance(rgb)), (height, width))
    brightest = envmap.pixel_directions(height, width)[i, j]
    pixel_angle = math.pi / height
    assert math.acos(min(1.0, float(brightest @ expected))) < pixel_angle


def test_sun_carries_its_direct_normal_irradiance(tool, bundled_sky, generated_sky):
    rgb = bundled_sky[0]["beauty"]
    without_sun, _ = tool.sky(with_sun=False)
    sun = tool.sun_direction()
    height, width = rgb.shape[:2]
    weight = envmap.solid_angles(height, width) * (envmap.pixel_directions(height, width) @ sun)
    upper = slice(0, height // 2)
    disc = np.einsum("hw,hwc->c", weight[upper], (rgb - without_sun)[upper])
    expected = LUMINOUS_EFFICACY * luminance(disc)
    assert expected == pytest.approx(generated_sky[1]["direct_normal_illuminance_lux"], rel=1e-3)


def test_sky_irradiance_is_plausible(bundled_sky, generated_sky):
    rgb = bundled_sky[0]["beauty"]
    numbers = generated_sky[1]
    lux = LUMINOUS_EFFICACY * luminance(envmap.irradiance(rgb))
    assert lux == pytest.approx(numbers["global_horizontal_illuminance_lux"], rel=1e-3)
    # clear sky, sun at 35 degrees: some 50-100 klux, 500-900 W/m^2 over the whole spectrum
    assert 50_000.0 < lux < 100_000.0
    assert 500.0 < numbers["global_horizontal_irradiance_broadband_w_m2"] < 900.0
    assert numbers["diffuse_horizontal_illuminance_lux"] < 0.5 * lux


def test_ground_is_the_grey_lambertian_reflection(bundled_sky, tool):
    rgb = bundled_sky[0]["beauty"]
    ground = rgb[-1, 0]
    assert np.allclose(rgb[rgb.shape[0] // 2 :], ground, rtol=1e-4)
    assert np.allclose(ground, tool.GROUND_ALBEDO / math.pi * envmap.irradiance(rgb), rtol=1e-3)
