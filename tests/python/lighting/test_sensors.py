"""Sensor kinds (patina.lighting.sensors): EN 13201-3's cylindrical and semi-cylindrical
illuminance are the mean of vertical planar sensors round the cylinder's curved surface."""

from __future__ import annotations

import numpy as np
import pytest

from patina.lighting.sensors import Sensors


@pytest.mark.parametrize("kind", ["cylindrical", "semicylindrical"])
def test_cylindrical_sensors_are_the_mean_of_planar_ones_round_the_cylinder(kind):
    rng = np.random.default_rng(3)
    u = rng.normal(size=(50, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    pts = np.zeros((50, 3))
    facing = 40.0
    sensors = Sensors.cylindrical(pts) if kind == "cylindrical" else Sensors.semicylindrical(pts, facing)
    # the curved surface's mean illuminance, numerically: vertical planes round the cylinder
    # (all of it, or the half within 90 degrees of the facing), over its whole perimeter
    phis = np.radians(np.arange(0.0, 360.0, 0.01))
    if kind == "semicylindrical":
        phis = np.radians(facing) + (phis - np.pi) / 2  # the half facing `facing`: 180 degrees
    normals = np.stack([np.cos(phis), np.zeros_like(phis), np.sin(phis)], axis=1)
    numeric = np.maximum(u @ normals.T, 0).mean(axis=1)
    np.testing.assert_allclose(sensors.response(u), numeric, atol=2e-4)


def test_a_vertical_sensor_sees_only_the_light_in_front_of_it():
    s = Sensors.vertical(np.zeros((2, 3)), 90.0)  # facing +z
    u = np.array([[0.0, 0.6, 0.8], [0.0, 0.6, -0.8]])
    np.testing.assert_allclose(s.response(u), [0.8, 0.0], atol=1e-15)
