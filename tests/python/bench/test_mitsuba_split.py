"""Mitsuba's switches in a child process: the vector width and wavefront flags take effect
(Dr.Jit reports the width asked for) and do not change the image (same spp, same seed)."""

from __future__ import annotations

import math

import pytest

from patina.bench.mitsuba_split import SWITCHES, run_child
from patina.bench.render import llvm_variant_works

pytest.importorskip("mitsuba")


def test_a_child_renders_at_the_width_and_mode_asked_for():
    if not llvm_variant_works():
        pytest.skip("Mitsuba's llvm_ad_rgb does not run here")
    spec = {"scene": "conductor-sphere", "size": [16, 12], "spp": 4, "threads": 2, "repeat": 1, "mesh": False}
    four = run_child({**spec, "vector_width": 4, "wavefront": True})
    default = run_child({**spec, "vector_width": 0, "wavefront": False})
    assert four["vector_width"] == 4
    assert len(four["seconds"]) == 1 and four["seconds"][0] > 0
    assert math.isfinite(four["mean"]) and four["mean"] > 0
    # the switches change how Mitsuba computes, not what: the same samples, the same image (to rounding)
    assert four["mean"] == pytest.approx(default["mean"], rel=1e-4)
    assert {s[0] for s in SWITCHES} == {"w8_vs_w4", "megakernel_vs_wavefront", "analytic_vs_mesh"}


def test_the_mesh_switch_gives_mitsuba_the_triangles_of_the_analytic_gold_sphere():
    from patina.bench.mitsuba_split import _scene_dict

    spec = {"scene": "conductor-sphere", "size": [16, 12]}
    assert _scene_dict({**spec, "mesh": False})["shape_0"]["type"] == "sphere"
    assert not isinstance(_scene_dict({**spec, "mesh": True})["shape_0"], dict)  # a mi.Mesh
