"""The block-step measure of structured artefacts (patina.bench.block_steps) on images whose
answer is known: independent noise steps alike everywhere, a mosaic of k x k blocks steps only
on its grid, and a mosaic of other blocks is not taken for one of k."""

from __future__ import annotations

import numpy as np
import pytest

from patina.bench.block_steps import BLOCK_SIZES, block_step_ratio, block_step_ratios


def mosaic(shape: tuple[int, int], k: int, rng: np.random.Generator) -> np.ndarray:
    blocks = rng.normal(size=(-(-shape[0] // k), -(-shape[1] // k)))
    return np.kron(blocks, np.ones((k, k)))[: shape[0], : shape[1]]


def test_independent_noise_steps_alike_on_and_off_the_grid():
    noise = np.random.default_rng(1).normal(size=(256, 320))
    for k in BLOCK_SIZES:
        assert block_step_ratio(noise, k) == pytest.approx(1.0, abs=0.05)


@pytest.mark.parametrize("k", BLOCK_SIZES)
def test_a_mosaic_of_k_blocks_under_noise_steps_on_its_grid(k):
    rng = np.random.default_rng(k)
    error = rng.normal(size=(192, 256)) + mosaic((192, 256), k, rng)
    assert block_step_ratio(error, k) > 1.2  # a mosaic as strong as the noise; half as strong: about 1.12
    assert block_step_ratio(error, k) == pytest.approx(block_step_ratio(error, 2 * k), rel=0.15)


def test_a_mosaic_of_eight_is_not_one_of_sixteen_lines_alone():
    rng = np.random.default_rng(3)
    error = rng.normal(size=(192, 256)) + 1.5 * mosaic((192, 256), 8, rng)
    assert block_step_ratio(error, 8) > 1.5
    assert block_step_ratio(error, 4) < block_step_ratio(error, 8)  # half of 4's lines are 8's


def test_the_ratios_are_of_the_luminance_error_against_the_reference():
    rng = np.random.default_rng(4)
    reference = rng.uniform(0.2, 1.0, size=(64, 64, 3))
    blocky = reference + (0.3 * mosaic((64, 64), 8, rng))[..., None]
    ratios = block_step_ratios(blocky, reference)
    assert set(ratios) == set(BLOCK_SIZES)
    assert ratios[8] > 10  # no noise: the error steps only on the grid
    assert block_step_ratios(reference, reference)[8] == 0.0  # no error, no steps (not a division by zero)


def test_a_grid_with_no_line_inside_the_image_is_left_out():
    rng = np.random.default_rng(5)
    small = rng.uniform(size=(12, 16, 3))
    assert set(block_step_ratios(small, small * 0.9)) == {4, 8}
    with pytest.raises(ValueError, match="no line of a 16-pixel grid"):
        block_step_ratio(small[..., 0], 16)


def test_a_few_outlying_pixels_on_a_line_do_not_make_a_mosaic():
    rng = np.random.default_rng(6)
    error = rng.normal(size=(128, 192))
    error[40:43, 95] = 500.0  # a sampled highlight beside the line x = 96: three pixels of 24576
    for k in BLOCK_SIZES:
        assert block_step_ratio(error, k) == pytest.approx(1.0, abs=0.05)


def test_stronger_noise_straddling_a_line_is_not_a_step():
    rng = np.random.default_rng(7)
    error = rng.normal(size=(128, 192))
    # a path-traced highlight whose noise is 40 times the rest's (the studio's car paint: 20 times
    # the cache's error elsewhere), across x = 96 and y = 32: 1.11 at k = 16 against the image's mean step
    error[26:38, 92:100] *= 40.0
    for k in BLOCK_SIZES:
        assert block_step_ratio(error, k) == pytest.approx(1.0, abs=0.05)
