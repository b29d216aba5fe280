"""How close a fit is (python/patina/fitting/metrics.py): relative errors floored near zero, and
CIEDE2000 between reflected colours."""

from __future__ import annotations

import numpy as np

from patina.fitting.metrics import colour_differences, relative_errors


def test_relative_errors_are_relative_away_from_zero():
    reference = np.array([1.0, 2.0, 4.0])
    assert np.allclose(relative_errors(reference, reference * 1.1), 0.1)


def test_relative_errors_floor_the_reference_at_a_thousandth_of_its_median():
    # a value 1e-9 off a zero measurement is a miss of 1e-9 / (1e-3 x median 1), not infinite
    reference = np.array([0.0, 1.0, 1.0])
    assert np.allclose(relative_errors(reference, np.array([1e-9, 1.0, 1.0])), [1e-6, 0.0, 0.0])


def test_identical_colours_differ_by_nothing_and_a_darker_one_by_more():
    rgb = np.array([[0.2, 0.1, 0.05], [0.05, 0.2, 0.1]])
    cos_i = np.array([1.0, 0.5])
    assert np.allclose(colour_differences(rgb, rgb, cos_i), 0.0)
    assert np.all(colour_differences(rgb, 0.5 * rgb, cos_i) > 5)
