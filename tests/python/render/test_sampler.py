"""The paths' random numbers (render/samplers/sample_numbers.h, docs/render.md): Owen-scrambled Sobol
points against SciPy's Sobol generator, their stratification (2-D discrepancy) and Monte
Carlo convergence against independent numbers; the sampler's scene key, option, argument
and EXR record; both samplers deterministic over widths and thread counts."""

from __future__ import annotations

import dataclasses
import itertools
import json
import os

import numpy as np
import pytest
from scipy.stats import qmc

from conftest import WIDTHS
from patina.cli import main
from patina.native import _core
from patina.render.images import read_exr_layers
from patina.render.run import PreparedScene, render
from patina.scene.reading import parse_scene
from quad_light import quad_light_floor, quad_light_scene
from repo_paths import ROOT

SEEDS = range(16)


def points(sampler: str, n: int, dims: int, seed: int = 0, first: int = 0) -> np.ndarray:
    return _core.sample_points(sampler, n, dims, seed=seed, first=first).astype(np.float64)


def test_unscrambled_points_are_scipys_sobol_points():
    # the (0, 2)-sequence every pair draws: Sobol's first two dimensions; SciPy draws in
    # Gray-code order: its point k is point k ^ (k >> 1) in the direct order
    n = 4096
    ours = _core.sample_points("sobol", n, 2, scramble=False).astype(np.float64)
    theirs = qmc.Sobol(2, scramble=False, bits=32).random(n)
    gray = np.arange(n) ^ (np.arange(n) >> 1)
    assert np.array_equal(ours[gray], np.floor(theirs * 2**24) / 2**24)
    with pytest.raises(ValueError, match="dims"):
        _core.sample_points("sobol", 1, 3, scramble=False)


# the sampler's columns (_core.sample_points): pixel x, y, lens u, v, then seven a bounce
PAIRS = [(0, 1), (2, 3), (5, 6), (8, 9), (12, 13), (15, 16)]  # a group's two uses, two bounces
DIMS = 17


def test_every_pair_of_uses_is_a_02_net_and_every_other_projection_stratified():
    # the L2-star discrepancy of 256 points, the mean over seeds, of every pair of the first
    # 17 uses (the camera's and two bounces'): a pair of one group (pixel, lens, light, BRDF)
    # is as low as the first two dimensions of SciPy's scrambled Sobol points (a (0, 2)-net,
    # 1/n nearly; higher dimension pairs of one Sobol sequence are not nets); uses of
    # different groups are paired at random, their projection below independent points'
    # (each use alone stratified)
    n = 256
    disc = {s: np.zeros((DIMS, DIMS)) for s in ("sobol", "independent", "scipy")}
    for sampler, seed in itertools.product(disc, SEEDS):
        x = qmc.Sobol(DIMS, seed=seed).random(n) if sampler == "scipy" else points(sampler, n, DIMS, seed)
        for i, j in itertools.combinations(range(DIMS), 2):
            disc[sampler][i, j] += qmc.discrepancy(x[:, [i, j]], method="L2-star") / len(SEEDS)
    ratio = disc["sobol"] / np.where(disc["independent"] > 0, disc["independent"], 1.0)
    for i, j in PAIRS:
        assert disc["sobol"][i, j] < 1.15 * disc["scipy"][0, 1], (i, j, ratio[i, j])
        assert ratio[i, j] < 0.16, (i, j, ratio[i, j])
    across = [(i, j) for i, j in itertools.combinations(range(DIMS), 2) if (i, j) not in PAIRS]
    assert max(ratio[i, j] for i, j in across) < 0.85, ratio
    assert np.median([ratio[i, j] for i, j in across]) < 0.65, ratio


def test_a_pixels_first_samples_put_one_position_in_each_stratum():
    # dimensions 0 and 1 (the pixel position) of any aligned block of 2^m samples: a
    # (0, m, 2)-net, so one point in each of the 2^a x 2^(m-a) strata
    for m, seed, block in itertools.product((4, 7), (0, 5), (0, 3)):
        n = 2**m
        x = points("sobol", n, 2, seed, first=block * n)
        for a in range(m + 1):
            cells = np.floor(x[:, 0] * 2**a) * 2 ** (m - a) + np.floor(x[:, 1] * 2 ** (m - a))
            assert len(np.unique(cells)) == n, (m, seed, block, a)


def _integrands():
    # smooth functions of the sampler's uses with their exact integrals, and how much faster
    # than independent numbers the scrambled (0, 2)-sequence must be at 1024 points. Uses of
    # one group (a pair, or a single use): scrambled nets, whose error on a smooth function
    # tends to n^-3/2 (a factor 64 from 64 to 1024 points, with log factors in 2-D: at least
    # 7). Uses of two groups are paired at random: their interaction is integrated at the
    # independent rate, here 1/25 of exp(x5 + x8)'s variance, so about 5 times less error.
    e1 = np.e - 1
    yield "exp(x0 + x1) (the pixel's)", (0, 1), lambda x: np.exp(x[:, 0] + x[:, 1]), e1**2, 8, 7
    cos_exact = np.real((np.exp(1j) - 1) / 1j * (np.exp(2j) - 1) / 2j)
    yield "cos(x5 + 2 x6) (the light's)", (5, 6), lambda x: np.cos(x[:, 0] + 2 * x[:, 1]), cos_exact, 8, 7
    yield "4 x8 x9 (the BRDF's)", (8, 9), lambda x: 4 * x.prod(axis=1), 1.0, 8, 7
    yield "exp(x4), exp(x10) (picks, roulette)", (4, 10), lambda x: np.exp(x[:, 0]) + np.exp(x[:, 1]), 2 * e1, 8, 7
    yield "exp(x5 + x8) (light and BRDF)", (5, 8), lambda x: np.exp(x[:, 0] + x[:, 1]), e1**2, 3, 3


@pytest.mark.parametrize("name, dims, f, exact, faster, falls", list(_integrands()),
                         ids=lambda v: v if isinstance(v, str) else "")  # fmt: skip
def test_monte_carlo_integration_converges_faster_than_with_independent_numbers(name, dims, f, exact, faster, falls):
    rmse = {}
    for sampler, n in itertools.product(("sobol", "independent"), (64, 1024)):
        errors = [f(points(sampler, n, max(dims) + 1, seed)[:, dims]).mean() - exact for seed in SEEDS]
        rmse[sampler, n] = float(np.sqrt(np.mean(np.square(errors))))
    assert rmse["sobol", 1024] < rmse["independent", 1024] / faster, rmse
    assert rmse["sobol", 1024] < rmse["sobol", 64] / falls, rmse
    assert rmse["independent", 1024] > rmse["independent", 64] / 6, rmse  # n^-1/2: a factor 4


def test_scrambles_differ_between_seeds_and_dimensions():
    a, b = points("sobol", 64, 8, seed=1), points("sobol", 64, 8, seed=2)
    assert not np.any(a == b)
    assert not np.array_equal(a[:, 2], a[:, 3])
    assert np.all((a >= 0) & (a < 1))


def test_a_render_under_a_quad_light_converges_faster_to_the_form_factor():
    # test_run.py's Lambert plane under a quad light, direct light: per pixel a 4-D integral
    # (pixel position, point on the light) against its exact value (Lambert's polygon form
    # factor, box-filtered); Sobol's relative RMSE is well below independent numbers' at the
    # same spp and falls at least as n^-1/2 (the pixel and light pairs are nets each, but
    # paired at random: their interaction converges at the independent rate)
    scene = scene_of(quad_light_scene(24, 16))
    expected, under = quad_light_floor(scene.camera, 8)
    prepared = PreparedScene(scene)
    rmse = {}
    for sampler, spp in itertools.product(("sobol", "independent"), (16, 64)):
        r = render(dataclasses.replace(scene, render=dataclasses.replace(scene.render, spp=spp)), prepared=prepared,
                   sampler=sampler)  # fmt: skip
        floor = np.isfinite(r.depth) & (r.depth > 4.5) & ~under
        rmse[sampler, spp] = float(np.sqrt(np.mean(((r.rgb[..., 0] - expected) / expected)[floor] ** 2)))
    assert rmse["sobol", 16] < rmse["independent", 16] / 4, rmse
    assert rmse["sobol", 64] < rmse["independent", 64] / 4, rmse
    assert rmse["sobol", 64] < rmse["sobol", 16] / 2, rmse
    assert rmse["independent", 64] > rmse["independent", 16] / 3, rmse  # n^-1/2: a factor 2


def small_scene(sampler: str | None = None, spp: int = 4) -> dict:
    render_settings = {"spp": spp, "integrator": "path", "max_depth": 5, "seed": 2}
    if sampler is not None:
        render_settings["sampler"] = sampler
    return {
        "version": 1,
        "camera": {"position": [0, 1, 4], "look_at": [0, 0.3, 0], "fov": 40, "width": 20, "height": 15},
        "render": render_settings,
        "materials": {
            "paint": {"type": "lambert", "albedo": [0.6, 0.3, 0.2]},
            "gold": {"type": "conductor", "metal": "Au", "roughness": 0.2},
        },
        "shapes": [
            {"type": "sphere", "radius": 0.5, "material": "gold", "transform": {"translate": [0, 0.5, 0]}},
            {"type": "plane", "material": "paint", "size": [10, 10]},
        ],
        "lights": [{"type": "quad", "center": [0, 3, 0], "u": [0.5, 0, 0], "v": [0, 0, 0.5], "radiance": 5}],
        "environment": {"type": "constant", "radiance": [0.3, 0.4, 0.5]},
    }


def scene_of(obj: dict):
    return parse_scene(obj, os.path.join(ROOT, "test.json"))


@pytest.mark.parametrize("sampler", ["sobol", "independent"])
@pytest.mark.parametrize("aa", ["uniform", "adaptive"])
def test_each_sampler_renders_the_same_bits_at_every_width_and_thread_count(sampler, aa):
    scene = scene_of(small_scene(sampler))
    prepared = PreparedScene(scene)
    first = render(scene, simd=WIDTHS[0], threads=1, prepared=prepared, aa=aa)
    assert first.sampler == sampler and np.isfinite(first.rgb).all() and first.rgb.max() > 0
    for w, threads in [(w, 2) for w in WIDTHS]:
        assert np.array_equal(first.rgb, render(scene, simd=w, threads=threads, prepared=prepared, aa=aa).rgb)


def test_the_samplers_draw_different_numbers_and_sobol_is_the_default():
    default = scene_of(small_scene())
    assert default.render.sampler == "sobol"
    prepared = PreparedScene(default)
    sobol = render(default, prepared=prepared)
    assert sobol.sampler == "sobol"
    assert np.array_equal(sobol.rgb, render(default, prepared=prepared, sampler="sobol").rgb)
    independent = render(default, prepared=prepared, sampler="independent")
    assert independent.sampler == "independent"
    assert not np.array_equal(sobol.rgb, independent.rgb)
    # the same image in expectation: the means over the image agree to the noise
    assert sobol.rgb.mean() == pytest.approx(independent.rgb.mean(), rel=0.1)


def test_bad_sampler_values_are_one_line_naming_the_key_or_option(tmp_path, capsys):
    obj = small_scene()
    for bad in (3, "halton", None):
        path = tmp_path / "bad.json"
        path.write_text(json.dumps({**obj, "render": {**obj["render"], "sampler": bad}}))
        assert main(["render", str(path), "--out", str(tmp_path / "x.exr"), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert "render.sampler" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    path = tmp_path / "s.json"
    path.write_text(json.dumps(obj))
    for command in (["render", str(path)], ["preview", os.path.join(ROOT, "materials", "red-plastic-iso.ptab")]):
        args = [*command, "--out", str(tmp_path / "y.exr"), "--sampler", "halton", "--quiet"]
        assert main(args) == 2
        err = capsys.readouterr().err
        assert "--sampler" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.exr").exists() and not (tmp_path / "y.exr").exists()
    scene = scene_of(obj)
    with pytest.raises(ValueError, match="sampler"):
        render(scene, sampler="halton")
    with pytest.raises(ValueError, match="sampler"):
        _core.RenderJob(PreparedScene(scene).core, _core.RenderOptions(spp=1, max_depth=2, sampler="halton"))
    with pytest.raises(ValueError, match="sampler"):
        _core.sample_points("halton", 4, 2)


def test_the_cli_option_overrides_the_scene_and_the_exr_header_records_it(tmp_path, capsys):
    path = tmp_path / "s.json"
    path.write_text(json.dumps(small_scene("sobol", spp=1)))
    out = tmp_path / "a.exr"
    assert main(["render", str(path), "--out", str(out), "--png", "none", "--sampler", "independent", "--quiet"]) == 0
    meta = read_exr_layers(str(out))[1]
    assert meta["patina:sampler"] == "independent"
    assert json.loads(meta["patina:scene"])["render"]["sampler"] == "independent"
    assert main(["render", str(path), "--out", str(out), "--png", "none", "--force", "--quiet"]) == 0
    assert read_exr_layers(str(out))[1]["patina:sampler"] == "sobol"
