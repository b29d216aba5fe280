"""The `profile` benchmark group: the integrator's stage timers account for a render's time and
work, and the breakdown table names every stage and kind."""

from __future__ import annotations

import pytest

from patina.bench import GROUPS
from patina.bench.profile import KINDS, breakdown_table, kind_seconds, median_stage_seconds
from patina.bundled import materials_path
from patina.native import _core
from patina.render.run import PreparedScene, path_depth
from patina.scene.reading import load_scene, with_overrides


@pytest.fixture(scope="module")
def tiny_preview():
    scene = with_overrides(load_scene(materials_path("scenes", "preview-ball.json")), width=24, height=18, spp=4)
    return scene, PreparedScene(scene)


@pytest.mark.parametrize("clock", ["wall", "cpu"])
def test_stage_times_count_the_work_and_fit_in_the_render_time(tiny_preview, clock):
    scene, prep = tiny_preview
    options = _core.RenderOptions(spp=4, max_depth=path_depth(scene), seed=0, threads=1, width=1, stage_clock=clock)
    job = _core.RenderJob(prep.core, options)
    job.start()
    job.wait()
    t = job.stage_times()
    stages = t.stages
    timed = {s for names in KINDS.values() for s in names} - {"sampler_film"}
    assert set(stages) == timed
    assert all(v >= 0 for v in stages.values())
    # the stages run inside the work items, so they sum to at most the items' time
    assert 0 < sum(stages.values()) <= t.item_seconds
    for s in ("trace_camera", "trace_secondary", "trace_shadow", "shading_points", "light_sample", "shade_sample"):
        assert stages[s] > 0, s
    assert t.camera_rays == 24 * 18 * 4
    # every camera ray that hits the ball or floor is a shading point; later bounces add more
    assert t.shading_points >= t.secondary_rays > 0
    assert 0 < t.shadow_rays <= t.shading_points


def test_medians_and_table_cover_every_stage(tiny_preview):
    scene, prep = tiny_preview
    widths = [1] + [w for w in (8,) if _core.width_supported(w)]
    medians = median_stage_seconds(prep, scene, widths, repeat=1)
    for w in widths:
        kinds = kind_seconds(medians[w])
        assert sum(kinds.values()) == pytest.approx(medians[w]["total"], rel=1e-6)
    table = breakdown_table(medians)
    for names in KINDS.values():
        for s in names:
            assert s in table
    assert all(f"= {k}" in table for k in KINDS)
    assert GROUPS["profile"].__name__ == "bench_profile"


def test_an_unknown_stage_clock_is_refused(tiny_preview):
    _, prep = tiny_preview
    with pytest.raises(ValueError, match="stage_clock: 'gpu' is not one of 'wall', 'cpu'"):
        _core.RenderJob(prep.core, _core.RenderOptions(spp=1, max_depth=2, stage_clock="gpu"))
