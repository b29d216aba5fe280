"""The benchmarks' convergence measures: relMSE with the outliers discarded, error-versus-time
interpolation on log-log axes, and references rendered once and kept on disk."""

from __future__ import annotations

import numpy as np
import pytest

from patina.bench import convergence as cv
from patina.bundled import materials_path
from patina.scene.reading import load_scene


def test_relmse_is_the_relative_squared_error_with_the_top_tenth_of_a_percent_discarded():
    rng = np.random.default_rng(1)
    ref = rng.uniform(0.5, 2.0, (50, 40, 3))
    scale = ref.mean()
    image = ref * 1.1
    expected = (((0.1 * ref / scale) ** 2) / ((ref / scale) ** 2 + cv.RELMSE_EPSILON)).mean(axis=-1).ravel()
    # 2000 pixels: the 2 largest errors are discarded
    worst = np.sort(expected)
    assert cv.relmse(image, ref) == pytest.approx(worst[:-2].mean(), rel=1e-12)
    # a firefly among them does not count ...
    spiked = image.copy()
    spiked[3, 4] = 1e6
    assert cv.relmse(spiked, ref) == pytest.approx(worst[:-1].mean(), rel=1e-3)
    # ... and the measure does not depend on the image's brightness
    assert cv.relmse(image * 7, ref * 7) == pytest.approx(cv.relmse(image, ref), rel=1e-12)
    # the reference's own error is subtracted, never below zero
    assert cv.relmse(image, ref, reference_error=0.001) == pytest.approx(cv.relmse(image, ref) - 0.001)
    assert 0 < cv.relmse(image, ref, reference_error=1.0) < 1e-6
    assert cv.relmse(ref, ref) == 0


def test_error_curve_interpolates_and_extrapolates_on_log_log_axes():
    # Monte Carlo: error = c / time
    times = [0.5, 2.0, 8.0]
    curve = cv.ErrorCurve(times, [3.0 / t for t in times])
    assert curve.seconds_for(3.0 / 1.3) == pytest.approx(1.3)
    assert curve.seconds_for(3.0 / 40) == pytest.approx(40)  # beyond the ladder
    assert curve.seconds_for(3.0 / 0.1) == pytest.approx(0.1)
    assert curve.error_at(4.0) == pytest.approx(0.75)
    # a segment where the error went up (noise) counts as falling with slope -1
    noisy = cv.ErrorCurve([1.0, 2.0], [1.0, 1.2])
    assert noisy.error_at(4.0) == pytest.approx(1.0 / 4.0)
    with pytest.raises(ValueError):
        cv.ErrorCurve([1.0], [1.0])


def test_the_reference_is_rendered_once_and_kept(tmp_path):
    path = materials_path("scenes", "cache-studio.json")
    scene = cv.sized(load_scene(path), 8)
    first = cv.reference(path, scene, 8, threads=1, folder=str(tmp_path))
    again = cv.reference(path, scene, 8, threads=1, folder=str(tmp_path))
    assert first.rendered and not again.rendered
    assert np.array_equal(first.image, again.image) and first.error == again.error > 0
    other = cv.reference(path, scene, 16, threads=1, folder=str(tmp_path))
    assert other.rendered and other.path != first.path
    assert np.isfinite(first.image).all() and first.image.shape == (6, 8, 3)
    # a damaged file is rendered again
    with open(first.path, "wb") as f:
        f.write(b"not an npz")
    assert cv.reference(path, scene, 8, threads=1, folder=str(tmp_path)).rendered
