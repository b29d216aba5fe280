"""The benchmarks' convergence measures: relMSE with the outliers discarded, error-versus-time
interpolation on log-log axes, and references rendered once and kept on disk."""

from __future__ import annotations

import numpy as np
import pytest

from patina.bench import convergence as cv
from patina.bundled import materials_path
from patina.render.run import PreparedScene, render
from patina.scene.reading import load_scene, with_overrides


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
    noisy = cv.ErrorCurve([1.0, 2.0, 4.0], [1.0, 1.2, 0.6])
    assert noisy.error_at(1.5) == pytest.approx(1.0 / 1.5)
    # beyond the ladder the curve goes on at slope -1 from its end, not along the end
    # segment's own slope (a firefly-carried error falls too slowly between two levels)
    flat = cv.ErrorCurve([1.0, 4.0], [1.0, 0.7])
    assert flat.error_at(8.0) == pytest.approx(0.7 / 2)
    assert flat.seconds_for(0.07) == pytest.approx(40.0)
    assert flat.error_at(0.5) == pytest.approx(2.0)
    with pytest.raises(ValueError):
        cv.ErrorCurve([1.0], [1.0])


def test_the_error_over_seeds_is_the_median_of_the_renders_relmse():
    ref = np.ones((40, 50, 3))
    images = [ref * (1 + d) for d in (0.1, 0.3, 0.2)]
    assert cv.median_relmse(images, ref) == pytest.approx(cv.relmse(images[2], ref))


def test_timed_renders_renders_each_run_with_successive_seeds():
    path = materials_path("scenes", "cache-studio.json")
    scene = with_overrides(cv.sized(load_scene(path), 8), spp=1)
    run = cv.Run(scene, PreparedScene(scene), 1)
    times, images = cv.timed_renders([run], 2)
    assert len(times) == 1 and times[0] > 0 and len(images[0]) == 3
    assert not np.array_equal(images[0][0], images[0][1])  # another seed, another image
    again = np.asarray(render(with_overrides(scene, seed=scene.render.seed + 1), threads=1).rgb, np.float64)
    assert np.array_equal(images[0][1], again)


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
