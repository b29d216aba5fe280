"""patina.render.envmap: the lat-long convention (Mitsuba 3's, y up), its inverse and pixel solid angles."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patina.render import envmap


@pytest.mark.parametrize(
    ("u", "v", "expected"),
    [
        (0.0, 0.5, (0.0, 0.0, -1.0)),
        (0.25, 0.5, (1.0, 0.0, 0.0)),
        (0.5, 0.5, (0.0, 0.0, 1.0)),
        (0.75, 0.5, (-1.0, 0.0, 0.0)),
        (0.3, 0.0, (0.0, 1.0, 0.0)),
        (0.3, 1.0, (0.0, -1.0, 0.0)),
        (0.125, 0.25, (0.5, math.sqrt(0.5), -0.5)),
    ],
)
def test_convention_anchors(u, v, expected):
    assert np.allclose(envmap.lat_long_direction(u, v), expected, atol=1e-12)


@settings(max_examples=200, deadline=None)
@given(u=st.floats(0.0, 1.0, exclude_max=True), v=st.floats(1e-6, 1.0 - 1e-6))
def test_uv_round_trip(u, v):
    back_u, back_v = envmap.direction_to_lat_long(envmap.lat_long_direction(u, v))
    assert float(back_v) == pytest.approx(v, abs=1e-9)
    # u is periodic: compare on the circle
    assert abs((float(back_u) - u + 0.5) % 1.0 - 0.5) < 1e-7
    assert 0.0 <= float(back_u) < 1.0


def test_direction_round_trip_and_scale_invariance():
    rng = np.random.default_rng(5)
    d = rng.normal(size=(1000, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    u, v = envmap.direction_to_lat_long(3.0 * d)
    assert np.all((u >= 0.0) & (u < 1.0) & (v >= 0.0) & (v <= 1.0))
    assert np.allclose(envmap.lat_long_direction(u, v), d, atol=1e-12)


@pytest.mark.parametrize(("height", "width"), [(1, 1), (3, 7), (256, 512), (512, 1024)])
def test_solid_angles_sum_to_the_sphere(height, width):
    omega = envmap.solid_angles(height, width)
    assert omega.shape == (height, width)
    assert omega.sum() == pytest.approx(4.0 * math.pi, rel=1e-12)
    assert np.all(omega > 0.0)
    assert np.allclose(omega, omega[::-1])  # north and south mirror


def test_solid_angle_of_a_pixel_matches_sin_theta_area():
    height, width = 512, 1024
    omega = envmap.solid_angles(height, width)
    theta = math.pi * (100 + 0.5) / height
    assert omega[100, 3] == pytest.approx(math.sin(theta) * (math.pi / height) * (2.0 * math.pi / width), rel=1e-5)


def test_pixel_directions_are_pixel_centres():
    d = envmap.pixel_directions(4, 8)
    assert d.shape == (4, 8, 3)
    assert np.allclose(d[1, 2], envmap.lat_long_direction(2.5 / 8, 1.5 / 4))


def test_constant_map_irradiance_is_pi():
    rgb = np.ones((256, 512, 3))
    assert np.allclose(envmap.irradiance(rgb), math.pi, rtol=1e-4)
    assert np.allclose(envmap.irradiance(rgb, (1.0, 0.0, 0.0)), math.pi, rtol=1e-3)
    # a map lit only from below gives nothing to a plane facing up
    rgb[:128] = 0.0
    assert np.allclose(envmap.irradiance(rgb), 0.0)


def test_bad_size():
    with pytest.raises(ValueError, match="positive"):
        envmap.solid_angles(0, 4)
