"""`patina render --workers 2` and the signals of a terminal or a service manager, sent to
the whole process group: SIGTERM keeps the first pass as Ctrl-C does; a second Ctrl-C aborts
at once. (Mirrors patina.batch.render_tiles with patina.signals; one cluster start each.)"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time

import pytest

from patina.render.images import read_exr_layers
from patina.signals import handling
from repo_paths import ROOT

pytest.importorskip("distributed")
BALL = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")


def start_group(out, width: int = 64) -> subprocess.Popen:
    """A render of many passes in a process group of its own (as a shell's job), started once
    it says it renders."""
    cmd = [sys.executable, "-m", "patina.cli", "render", BALL, "--spp", "100000", "--width", str(width)]
    with handling(signal.SIGINT, signal.default_int_handler):  # see tests/python/interrupts.py
        proc = subprocess.Popen(
            [*cmd, "--workers", "2", "--out", str(out)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
        )
    assert proc.stdout is not None
    for line in proc.stdout:
        if line.startswith(f"rendering {width}x"):
            return proc
    pytest.fail(f"the render did not start: {proc.communicate()[1]}")


def test_sigterm_to_the_process_group_keeps_the_first_pass(tmp_path):
    """Before: the workers died of it, a traceback (KeyboardInterrupt, FutureCancelledError,
    "lost its workers' results 3 times"), exit 1, nothing written."""
    proc = start_group(tmp_path / "ball.exr")
    time.sleep(1)
    os.killpg(proc.pid, signal.SIGTERM)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "PARTIAL" in out
    layers, meta = read_exr_layers(tmp_path / "ball.exr")
    assert meta["patina:complete"] == 0 and layers["beauty"].shape == (48, 64, 3)


def test_a_second_ctrl_c_aborts_at_once(tmp_path):
    """Before: about 10.5 s after the second Ctrl-C (the workers were asked to finish their task)."""
    proc = start_group(tmp_path / "ball.exr", width=192)
    time.sleep(1)
    os.killpg(proc.pid, signal.SIGINT)
    time.sleep(0.2)  # in the first pass still (192 x 144 pixels x 16 samples on 2 workers)
    sent = time.monotonic()
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert time.monotonic() - sent < 5, err
    assert proc.returncode == 130 and "Traceback" not in err, err
    # nothing, or (when the first pass ended before the second Ctrl-C came: a loaded machine's
    # timing) the partial image the first one keeps; never a half-written file
    if os.path.exists(tmp_path / "ball.exr"):
        assert read_exr_layers(tmp_path / "ball.exr")[1]["patina:complete"] == 0


def _children(pid: int) -> list[int]:
    found = []
    for task in os.listdir(f"/proc/{pid}/task"):
        with open(f"/proc/{pid}/task/{task}/children") as f:
            found += [int(c) for c in f.read().split()]
    return found


def test_ctrl_c_while_the_cluster_starts_stops_the_command(tmp_path):
    """Before: the Ctrl-C that came while the local cluster started was discarded; the render
    went on to its end and exited 0."""
    cmd = [sys.executable, "-m", "patina.cli", "render", BALL, "--spp", "4", "--width", "64", "--workers", "2"]
    with handling(signal.SIGINT, signal.default_int_handler):
        proc = subprocess.Popen(
            [*cmd, "--out", str(tmp_path / "ball.exr")],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
        )
    deadline = time.monotonic() + 60
    while not _children(proc.pid) and time.monotonic() < deadline:  # the cluster's first process
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, out + err
    assert "rendered" not in out and err.strip().splitlines()[-1] == "patina: interrupted", err
    assert not os.path.exists(tmp_path / "ball.exr")


def test_a_ctrl_c_as_the_command_exits_keeps_its_status(tmp_path):
    """Before: killed by the signal (status -2) when it came while the interpreter finalised,
    after the first Ctrl-C's partial image was written (Python hands SIGINT back to the default
    action then); a fast machine finished the first pass before the test's second Ctrl-C."""
    proc = start_group(tmp_path / "ball.exr")
    time.sleep(1)
    os.killpg(proc.pid, signal.SIGINT)
    assert proc.stdout is not None
    for line in proc.stdout:  # the command's stdout is flushed as it returns: "wrote" comes then
        if line.startswith("wrote "):
            with contextlib.suppress(ProcessLookupError):  # gone already
                os.killpg(proc.pid, signal.SIGINT)
            break
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and "Traceback" not in err, err
    assert read_exr_layers(tmp_path / "ball.exr")[1]["patina:complete"] == 0
