"""patina batch on Dask distributed: a LocalCluster of 2 worker processes gives the in-process
results; a rerun skips everything; a worker killed mid-task loses nothing; the command's own
LocalCluster prints its dashboard."""

from __future__ import annotations

import glob
import os
import threading

import pytest
from batch_library import BAD, GOOD, QUICK
from dask_workers import kill_a_busy_worker, wait_for_live_workers

from patina.batch import run_batch
from patina.batch.manifest import checksum
from patina.cli import main

distributed = pytest.importorskip("distributed")


def on_dask(library: str, out: str, client, settings=QUICK) -> dict:
    return run_batch(library, out, settings, client=client, progress=False, say=lambda line: None)


def statuses(summary: dict) -> dict:
    return {m["name"]: (m["status"], m["validation"], m["best_model"]) for m in summary["materials"]}


def test_the_cluster_gives_the_in_process_results_and_a_rerun_skips(finished_once, tmp_path, client):
    library, here = finished_once.library, finished_once.summary
    out = str(tmp_path / "there")
    there = on_dask(library, out, client)
    assert statuses(there) == statuses(here)
    bad = {m["name"]: m for m in there["materials"]}[BAD]
    assert bad["status"] == "failed" and bad["error"] == {m["name"]: m for m in here["materials"]}[BAD]["error"]
    for name in GOOD:
        assert os.path.isfile(os.path.join(out, "materials", name, "preview.png"))
    again = on_dask(library, out, client)
    assert again["counts"]["tasks_run"] == 0


def test_a_worker_killed_mid_task_loses_nothing(library, tmp_path, client_to_kill):
    client = client_to_kill
    out = str(tmp_path / "out")
    killed: list[str] = []
    stop = threading.Event()
    killer = threading.Thread(target=kill_a_busy_worker, args=(client, killed, stop), daemon=True)
    killer.start()
    try:
        summary = on_dask(library, out, client)
    finally:
        stop.set()
        killer.join()
    assert killed, "no worker was seen running a task"
    assert statuses(summary)[BAD][0] == "failed"
    assert all(statuses(summary)[n][0] == "ok" for n in GOOD), summary["materials"]
    # nothing half-written: every output a manifest lists is whole, no temporary is left beside them
    for manifest in glob.glob(os.path.join(out, "materials", "*", "*.manifest.json")):
        assert os.path.getsize(manifest) > 0
    for name in GOOD:
        folder = os.path.join(out, "materials", name)
        assert not [n for n in os.listdir(folder) if ".tmp" in n]
        assert checksum(os.path.join(folder, "preview.png"))
    wait_for_live_workers(client, 1)  # the dead one dropped (its nanny may have restarted it)
    assert on_dask(library, out, client)["counts"]["tasks_run"] == 0  # and every task was complete


def test_the_command_runs_its_own_local_cluster(library, tmp_path, capsys):
    code = main(["batch", library, "--out", str(tmp_path / "out"), "--workers", "1", "--steps", "validate", "--quiet"])
    assert code == 0
    code = main(["batch", library, "--out", str(tmp_path / "out"), "--workers", "1", "--steps", "validate"])
    printed = capsys.readouterr().out
    assert code == 0 and "running on a local Dask cluster of 1 worker process; dashboard: " in printed


def test_the_command_on_a_running_scheduler(library, tmp_path, client, capsys):
    address = client.scheduler.address
    out = str(tmp_path / "out")
    assert main(["batch", library, "--out", out, "--scheduler", address, "--steps", "validate"]) == 0
    printed = capsys.readouterr().out
    assert f"running on the Dask scheduler at {address} (2 workers)" in printed
    assert main(["batch", library, "--out", out, "--scheduler", address, "--workers", "2"]) == 2
    err = capsys.readouterr().err
    assert "--workers: sets the size of the local cluster" in err and len(err.strip().splitlines()) == 1
