"""patina.batch.scheduling at the edges: an output folder that cannot be written is refused
before any task; SIGTERM ends a batch as Ctrl-C does (exit 130, one line, no temporary)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest
from batch_library import QUICK

from interrupts import start_interruptible
from patina.batch import IN_PROCESS, run_batch


@pytest.fixture
def read_only_folder(tmp_path):
    """An existing report folder (materials/ in it) nobody may write: a tmpfs remounted
    read-only (root writes anywhere else)."""
    folder = tmp_path / "read-only"
    folder.mkdir()
    if os.geteuid() != 0:
        (folder / "materials").mkdir()
        folder.chmod(0o555)
        (folder / "materials").chmod(0o555)
        yield str(folder)
        return
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", folder], check=False).returncode:
        pytest.skip("cannot mount a tmpfs here")
    (folder / "materials").mkdir()
    subprocess.run(["mount", "-o", "remount,ro", folder], check=True)
    try:
        yield str(folder)
    finally:
        subprocess.run(["umount", folder], check=False)


def test_an_unwritable_out_folder_is_refused_before_any_task(library, read_only_folder, monkeypatch):
    """Before: every task ran, then "cannot write: Permission denied", exit 2."""
    ran: list[str] = []
    monkeypatch.setattr("patina.batch.scheduling.run_in_process", lambda *a: ran.append("a task") or [])
    with pytest.raises(ValueError, match=r"^--out .*summary.json: cannot write: (Read-only file system|Permission)"):
        run_batch(library, read_only_folder, QUICK, scheduler=IN_PROCESS, progress=False, say=lambda line: None)
    assert ran == []


def test_sigterm_ends_a_batch_as_ctrl_c_does(library, tmp_path):
    """Before: SIGTERM killed `batch` (exit 143, a "leaked semaphore" warning)."""
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "patina.cli", "batch", library, "--out", str(out), "--scheduler", IN_PROCESS]
    proc = start_interruptible([*cmd, "--models", "ggx+lambert", "--starts", "1", "--spp", "1"])
    assert proc.stdout is not None
    for line in proc.stdout:
        if line.startswith("running in this process"):
            break
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and err.strip().splitlines()[-1] == "patina: interrupted"
    leftovers = [n for _, _, names in os.walk(out) for n in names if ".tmp" in n]
    assert leftovers == []
