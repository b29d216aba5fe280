"""A render's tiles as Dask tasks (patina.batch.render_tiles): the files a scene reads shipped
with it; the tasks' chain of tile sums merged into the very image the local render makes (in
this process, then on a LocalCluster of 2 worker processes); each worker prepares the scene
once; Ctrl-C keeps whole passes; the command, and a scheduler that does not answer."""

from __future__ import annotations

import functools
import os
import threading
import time

import numpy as np
import pytest
from dask_workers import kill_a_busy_worker

from patina.batch import render_tiles
from patina.bundled import materials_path
from patina.cli import main
from patina.native import _core
from patina.render.images import read_image
from patina.render.prepare import PreparedScene
from patina.render.run import RenderAborted, job_settings, new_job, render
from patina.scene.reading import load_scene, with_overrides

IMAGES = ("rgb", "albedo", "normal", "depth", "illuminance", "samples", "aa_level", "aa_rays")


def _scene(**overrides):
    """The preview ball (a table under the clear coat, the studio map: files to ship), 32 x 24."""
    return with_overrides(load_scene(materials_path("scenes", "preview-ball.json")), width=32, height=24, **overrides)


@functools.cache
def _prepared() -> PreparedScene:
    """_scene() prepared once (its spp, seed and sampler are the job's, not the prepared scene's)."""
    return PreparedScene(_scene())


def _local(scene):
    return render(scene, threads=2, prepared=_prepared())


def assert_same_image(a, b, same_rays: bool = True) -> None:
    for name in IMAGES:
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            assert np.array_equal(x, y), f"{name} differs"
    assert (a.camera_rays, a.spp, a.aa) == (b.camera_rays, b.spp, b.aa)
    assert a.rays == b.rays or not same_rays


# ---------------------------------------------------------------- in this process


def test_the_bundle_holds_every_file_the_scene_reads():
    ball = _scene()
    assert [os.path.basename(p) for p in render_tiles.scene_files(ball)] == ["carpaint-base.ptab", "studio.exr"]
    mesh = render_tiles.scene_files(load_scene(materials_path("scenes", "aa-checkerboard.json")))
    assert [os.path.splitext(p)[1] for p in mesh] == [".obj"]
    luminaire = render_tiles.scene_files(load_scene(materials_path("scenes", "street-luminaire.json")))
    assert luminaire and all(os.path.isfile(p) for p in luminaire)
    bundle = render_tiles.bundle_scene(ball, job_settings(ball))
    for path in render_tiles.scene_files(ball):
        with open(path, "rb") as f:
            assert bundle.files[path] == f.read()
    # the checksum names the settings too: another seed is another job of the same prepared scene
    other = render_tiles.bundle_scene(ball, job_settings(with_overrides(ball, seed=1)))
    assert other.checksum != bundle.checksum and other.scene_checksum == bundle.scene_checksum


@pytest.mark.parametrize("tiles, groups", [(1, 8), (12, 8), (12, 5), (300, 8)])
def test_tile_groups_cover_the_tiles_in_order(tiles, groups):
    plan = render_tiles.tile_groups(tiles, groups)
    assert len(plan) == min(tiles, groups) and all(plan)
    assert sorted(t for g in plan for t in g) == list(range(tiles))
    assert all(list(g) == sorted(g) for g in plan)  # a task locks its tiles in increasing order


@pytest.mark.parametrize("passes", [1, 2, 8, 9, 1000])
def test_pass_runs_start_with_the_first_pass_alone_and_cover_the_passes(passes):
    runs = render_tiles.pass_runs(passes)
    assert runs[0] == (0, 1) and len(runs) <= render_tiles.PASS_RUNS
    assert [p for first, end in runs for p in range(first, end)] == list(range(passes))


def test_a_small_render_is_few_tasks_and_a_big_one_many():
    # 2 threads; tiles, passes, samples
    assert render_tiles.task_shape(4, 4, 2, 32 * 24 * 4) == (2, 2)  # one group a thread, the first pass alone
    assert render_tiles.task_shape(1, 1, 2, 16 * 16) == (1, 1)
    big = render_tiles.task_shape(2040, 64, 2, 3840 * 2160 * 1024)
    assert big == (render_tiles.GROUPS_PER_THREAD * 2, render_tiles.PASS_RUNS)
    groups, runs = render_tiles.task_shape(108, 8, 2, 192 * 144 * 64)
    assert 2 <= groups and 2 <= runs and groups * runs <= 192 * 144 * 64 // render_tiles.MIN_TASK_SAMPLES


def _tasks_in_process(scene, groups: int):
    """The Dask tasks' work run here, one after the other, merged as render_on_dask merges it."""
    settings = job_settings(scene)
    bundle = render_tiles.bundle_scene(scene, settings)
    merged = new_job(_prepared(), settings, threads=1)
    for tiles in render_tiles.tile_groups(merged.tile_count, groups):
        before = None
        for passes in render_tiles.pass_runs(merged.pass_count):
            before = render_tiles.render_passes(bundle, tiles, passes, before)
        for tile in tiles:
            merged.write_tile(tile, **before["tiles"][tile])
    return merged.resolve(), before


@pytest.mark.parametrize("aa", ["uniform", "adaptive"])
def test_tiles_rendered_in_chained_tasks_give_the_local_image_bit_for_bit(aa):
    scene = _scene(aa=aa, spp=3)
    images, _ = _tasks_in_process(scene, groups=3)
    local = _local(scene)
    for name in IMAGES:
        if getattr(local, name) is not None:
            assert np.array_equal(getattr(images, name), getattr(local, name)), name
    assert (images.aa_level is not None) == (aa == "adaptive")


def test_a_worker_job_with_another_renders_sums_starts_its_first_pass_from_zero():
    scene = _scene(spp=2)
    first, _ = _tasks_in_process(scene, groups=2)
    again, _ = _tasks_in_process(scene, groups=3)  # the cached worker job still holds the first run's sums
    assert np.array_equal(first.rgb, again.rgb)


def test_write_tile_checks_what_it_is_given():
    scene = _scene(spp=1)
    job = _core.RenderJob(_prepared().core, job_settings(scene))
    sums = job.read_tile(0)["sums"]
    with pytest.raises(ValueError, match="tile 0: sums must have shape"):
        job.write_tile(0, sums[:, :-1])
    with pytest.raises(ValueError, match="aa_level and aa_rays are the adaptive sampler's"):
        job.write_tile(0, sums, np.zeros(sums.shape[:2], np.uint8), np.zeros(sums.shape[:2], np.uint8))
    with pytest.raises(IndexError):
        job.render_tiles([0, job.tile_count], 0, 1)
    with pytest.raises(IndexError):
        job.render_tiles([0], 0, job.pass_count + 1)


# ---------------------------------------------------------------- on a LocalCluster of 2 worker processes


@pytest.mark.parametrize("aa", ["uniform", "adaptive"])
def test_the_distributed_render_is_the_local_one_bit_for_bit(client, aa):
    scene = _scene(aa=aa, spp=4)  # 4 passes: a group's tasks, the first pass then the other three
    there = render_tiles.render_on_dask(scene, client, prepared=_prepared())
    here = _local(scene)
    assert there.complete and not there.interrupted and there.threads == 2
    assert_same_image(there, here)


@pytest.mark.parametrize("integrator, train_passes", [("cache", 0), ("cache-guided", 0), ("cache-guided", 2)])
def test_the_radiance_cache_renders_on_the_cluster_as_here_bit_for_bit(client, integrator, train_passes):
    # a work item's cache starts from its image regions' points, which depend on the region
    # alone (render/cache/cache_regions.h), so a tile is the same in any process; each
    # process builds the regions its tiles want, so the cluster may build more cache points.
    # cache-guided's trained guide (train_passes > 0) is trained by each process for the whole
    # image, the same guide as here, and no cache points are built
    scene = with_overrides(_scene(integrator=integrator, spp=2), cache_train_passes=train_passes)
    there = render_tiles.render_on_dask(scene, client, prepared=_prepared(), groups=4)
    here = _local(scene)
    assert there.complete
    assert_same_image(there, here, same_rays=False)  # the regions' rays, traced in each process
    assert there.rays >= here.rays
    # the items' queries are the same; the regions' pre-pass queries and their texels are
    # counted by every process that builds the region
    assert there.cache_queries == here.cache_queries
    counts = ("cache_texels_reprojected", "cache_texels_traced")
    assert all(getattr(there, k) >= getattr(here, k) for k in counts)
    if integrator == "cache-guided" and train_passes > 0:
        assert there.cache_points == here.cache_points == 0
    else:
        assert there.cache_points >= here.cache_points > 0


def test_each_worker_prepares_the_scene_once(client):
    scene = _scene(spp=2, seed=7)
    checksum = render_tiles.bundle_scene(scene, job_settings(scene)).scene_checksum
    for seed in (7, 8):  # another seed: another job, the same prepared scene
        render_tiles.render_on_dask(with_overrides(scene, seed=seed), client, prepared=_prepared(), groups=8)
    prepared = client.run(lambda: render_tiles.prepared_here.count(checksum))
    assert 1 <= sum(prepared.values()) and all(n <= 1 for n in prepared.values()), prepared


def test_a_worker_killed_mid_render_loses_nothing(client_to_kill):
    client = client_to_kill
    scene = _scene(spp=32)
    killed: list[str] = []
    stop = threading.Event()
    killer = threading.Thread(target=kill_a_busy_worker, args=(client, killed, stop), daemon=True)
    killer.start()
    try:
        there = render_tiles.render_on_dask(scene, client, prepared=_prepared())
    finally:
        stop.set()
        killer.join()
    assert killed, "no worker was seen running a task"
    assert there.complete
    assert_same_image(there, _local(scene))  # the dead worker's chains were computed again elsewhere


def _interrupt_at(monkeypatch, calls: set[int]) -> None:
    """Ctrl-C while render_on_dask waits for its tasks, at the given waits (1: the first)."""
    count = [0]
    wait = render_tiles._wait

    def interrupted(news, seconds):
        count[0] += 1
        if count[0] in calls:
            raise KeyboardInterrupt
        wait(news, seconds)

    monkeypatch.setattr(render_tiles, "_wait", interrupted)


def test_ctrl_c_keeps_the_finished_passes_of_every_tile(client, monkeypatch):
    scene = _scene(spp=16)  # 8 passes of 2 samples
    _interrupt_at(monkeypatch, {1})  # right after the tasks are submitted
    result = render_tiles.render_on_dask(scene, client, prepared=_prepared())
    assert result.interrupted and not result.complete
    # every pixel got whole passes (2 samples each); with the uniform sampler a pixel's first n
    # samples are those of the render at n spp, added in the same order: bit for bit
    counts = np.unique(result.samples)
    assert counts.min() >= 2 and all(n % 2 == 0 for n in counts) and counts.min() < 16
    for n in counts:
        local = _local(with_overrides(scene, spp=int(n)))
        where = result.samples == n
        assert np.array_equal(result.rgb[where], local.rgb[where]), n


def test_a_second_ctrl_c_aborts(client, monkeypatch):
    _interrupt_at(monkeypatch, {1, 2})
    with pytest.raises(RenderAborted):
        render_tiles.render_on_dask(_scene(spp=16), client, prepared=_prepared())


def test_the_command_on_a_running_scheduler_writes_the_local_render(client, tmp_path, capsys):
    scene = materials_path("scenes", "preview-ball.json")
    common = ["render", scene, "--width", "32", "--spp", "2", "--png", "none", "--quiet"]
    there, here = str(tmp_path / "there.exr"), str(tmp_path / "here.exr")
    assert main([*common, "--out", there, "--scheduler", client.scheduler.address]) == 0
    assert main([*common, "--out", here]) == 0
    assert np.array_equal(read_image(there), read_image(here))
    assert main([*common, "--out", here, "--force", "--scheduler", client.scheduler.address, "--threads", "2"]) == 2
    err = capsys.readouterr().err
    assert "--threads" in err and len(err.strip().splitlines()) == 1


def test_an_unreachable_scheduler_fails_within_seconds_with_one_line(tmp_path, capsys):
    pytest.importorskip("distributed")
    started = time.monotonic()
    scene = materials_path("scenes", "preview-ball.json")
    code = main(["render", scene, "--out", str(tmp_path / "a.exr"), "--scheduler", "tcp://127.0.0.1:9"])
    err = capsys.readouterr().err
    assert code == 2 and "tcp://127.0.0.1:9" in err and len(err.strip().splitlines()) == 1, err
    assert time.monotonic() - started < 30
    assert not os.path.exists(tmp_path / "a.exr")


def _gltf_scene(folder) -> object:
    """A scene of a .gltf whose buffer is an external .bin in a subfolder (as exporters write
    them; its URI as trimesh reads it, not percent-decoded)."""
    import json as json_module

    import trimesh

    from patina.scene.reading import parse_scene

    os.makedirs(folder / "buffers")
    vertices = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], np.float32)
    (folder / "buffers" / "tri%20data.bin").write_bytes(vertices.tobytes() + np.array([0, 1, 2], np.uint32).tobytes())
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"uri": "buffers/tri%20data.bin", "byteLength": 48}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 12},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5125, "count": 3, "type": "SCALAR"},
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    (folder / "tri.gltf").write_text(json_module.dumps(gltf))
    assert len(trimesh.load(folder / "tri.gltf", force="mesh").faces) == 1
    doc = {
        "version": 1,
        "camera": {"position": [0, 0, 3], "look_at": [0, 0, 0], "fov": 60, "width": 16, "height": 16},
        "render": {"spp": 1, "integrator": "direct"},
        "materials": {"grey": {"type": "lambert", "albedo": [0.5, 0.5, 0.5]}},
        "shapes": [{"type": "mesh", "file": "tri.gltf", "material": "grey"}],
        "environment": {"type": "constant", "radiance": [1, 1, 1]},
    }
    return parse_scene(doc, str(folder / "scene.json"))


def test_a_gltf_reaches_the_workers_with_its_external_buffers(tmp_path):
    """Before: only the .gltf was sent; a worker (without this machine's files) failed to read
    its .bin ("Compute Failed"). Here the worker's side runs on the bundle alone: the scene's
    folder is gone when it is prepared."""
    folder = tmp_path / "scene"
    scene = _gltf_scene(folder)
    bundle = render_tiles.bundle_scene(scene, job_settings(scene))
    assert list(bundle.companions[str(folder / "tri.gltf")]) == [os.path.join("buffers", "tri%20data.bin")]
    os.rename(folder, tmp_path / "elsewhere")
    prepared = render_tiles._prepare(bundle)
    assert prepared.triangles == 1


def test_a_gltf_naming_a_file_outside_its_folder_is_refused(tmp_path):
    with pytest.raises(ValueError, match=r"only files in the \.gltf's folder"):
        render_tiles.gltf_companions("a.gltf", b'{"buffers": [{"uri": "../../etc/passwd"}]}')
    assert (
        render_tiles.gltf_companions("a.gltf", b'{"buffers": [{"uri": "data:application/octet-stream;base64,AA=="}]}')
        == []
    )
    assert render_tiles.gltf_companions("a.gltf", b"not json") == []
