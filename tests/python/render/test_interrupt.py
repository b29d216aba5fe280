"""Interrupting `patina render` for real: a subprocess sent SIGINT or SIGTERM at chosen
moments. The output is a valid image in which every pixel has a sample, or absent; no
temporary file is left; a write is never cut in half; a writer killed mid-write (SIGKILL)
leaves a temporary that the next write beside it removes."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from interrupts import start_interruptible
from patina.cli import main
from patina.render.images import read_exr_layers
from repo_paths import ROOT

BALL = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")
FIRST_PASS_SPP = 16  # RenderOptions::max_pass_spp: the first pass of a render of many samples


def start(out, *options: str) -> subprocess.Popen:
    # one thread and a large first pass (128 x 96 x 16 samples of the ball, ~1-2 s), so a
    # signal sent as the render starts arrives inside the first pass
    cmd = [sys.executable, "-m", "patina.cli", "render", BALL, "--out", str(out), "--spp", "1000000"]
    cmd += ["--width", "128", "--threads", "1", *options]
    proc = start_interruptible(cmd)
    assert proc.stdout is not None and proc.stdout.readline().startswith("rendering")
    return proc


def interrupt_twice(proc: subprocess.Popen, second: signal.Signals, timeout: float = 60) -> str:
    """SIGINT, then `second` once the render has said it took the first (two signals sent
    together can be one: Python keeps one pending flag per signal, and a loaded machine may
    run the handler only after both arrived); what it wrote on stderr meanwhile."""
    assert proc.stderr is not None
    stderr = proc.stderr
    lines: list[str] = []
    took = threading.Event()

    def read() -> None:
        for line in stderr:
            lines.append(line)
            if "interrupted: finishing the first pass" in line:
                took.set()
                return

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    proc.send_signal(signal.SIGINT)
    if not took.wait(timeout):
        proc.kill()
        raise AssertionError(f"no word of the first interrupt within {timeout} s: {''.join(lines)!r}")
    reader.join()  # it read up to that line: communicate() reads the rest
    proc.send_signal(second)
    return "".join(lines)


def finish(proc: subprocess.Popen) -> tuple[str, str]:
    try:
        return proc.communicate(timeout=120)
    finally:
        proc.kill()


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_in_the_first_pass_keeps_a_whole_first_pass(tmp_path, sig):
    out = tmp_path / "x.exr"
    proc = start(out)
    time.sleep(0.1)
    proc.send_signal(sig)
    stdout, stderr = finish(proc)
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr and "finishing the first pass" in stderr
    layers, meta = read_exr_layers(str(out))
    assert int(meta["patina:complete"]) == 0
    # every pixel has the whole first pass (it used to be 0: a quarter of the tiles black)
    assert int(meta["patina:samples_min"]) >= FIRST_PASS_SPP
    assert np.isfinite(layers["beauty"]).all() and (layers["beauty"].max(axis=2) > 0).mean() > 0.99
    assert f"at least {meta['patina:samples_min']} of 1000000 spp" in stdout
    assert sorted(os.listdir(tmp_path)) == ["x.exr", "x.png"]  # no temporaries


def test_a_second_interrupt_aborts_and_writes_nothing(tmp_path):
    out = tmp_path / "x.exr"
    proc = start(out)
    time.sleep(0.1)
    first = interrupt_twice(proc, signal.SIGTERM)  # the second interrupt may be either signal
    _, rest = finish(proc)
    stderr = first + rest
    assert proc.returncode == 130, stderr
    assert "Traceback" not in stderr
    assert "aborted, nothing written" in stderr.strip().splitlines()[-1]
    assert os.listdir(tmp_path) == []


def test_an_existing_output_survives_an_aborted_render(tmp_path):
    out = tmp_path / "x.exr"
    out.write_bytes(b"an earlier render")
    proc = start(out, "--force")
    time.sleep(0.1)
    first = interrupt_twice(proc, signal.SIGINT)
    _, rest = finish(proc)
    stderr = first + rest
    assert proc.returncode == 130, stderr
    assert out.read_bytes() == b"an earlier render" and sorted(os.listdir(tmp_path)) == ["x.exr"]


def test_a_signal_while_writing_waits_until_the_outputs_are_whole(tmp_path, monkeypatch, capsys):
    import patina.cli.render as cli_render

    real = cli_render.write_outputs

    def write_then_terminated(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)  # arrives at the first bytecode of the write
        time.sleep(0.05)
        real(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(cli_render, "write_outputs", write_then_terminated)
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    out = tmp_path / "x.exr"
    scene = os.path.join(ROOT, "materials", "scenes", "diffuse-sphere.json")
    assert main(["render", scene, "--out", str(out), "--spp", "1", "--width", "32", "--quiet"]) == 130
    assert "interrupted while writing: the outputs were finished first" in capsys.readouterr().err
    layers, meta = read_exr_layers(str(out))
    assert int(meta["patina:complete"]) == 1 and layers["beauty"].shape[1] == 32
    assert sorted(os.listdir(tmp_path)) == ["x.exr", "x.png"]
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before  # handlers restored


def test_a_writer_killed_mid_write_leaves_a_temporary_the_next_run_removes(tmp_path):
    # a writer that dies by SIGKILL while writing (no handler can run) leaves its temporary
    code = (
        "import os, sys, time\n"
        "from patina.atomic import atomic_output\n"
        "def write(tmp):\n"
        "    open(tmp, 'wb').write(b'half' * 1000)\n"
        "    print(tmp, flush=True)\n"
        "    time.sleep(60)\n"
        "atomic_output(sys.argv[1], write)\n"
    )
    out = tmp_path / "x.exr"
    proc = subprocess.Popen([sys.executable, "-c", code, str(out)], stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    tmp = proc.stdout.readline().strip()
    proc.kill()
    proc.wait()
    assert os.path.basename(tmp) in os.listdir(tmp_path) and not out.exists()
    # a live writer's temporary beside the same output must stay
    live = tmp_path / f".x.p{os.getpid()}.abcdefgh.tmp.exr"
    live.write_bytes(b"in progress")
    scene = os.path.join(ROOT, "materials", "scenes", "diffuse-sphere.json")
    assert main(["render", scene, "--out", str(out), "--spp", "1", "--width", "16", "--quiet"]) == 0
    assert sorted(os.listdir(tmp_path)) == sorted([live.name, "x.exr", "x.png"])
    assert json.loads(str(read_exr_layers(str(out))[1]["patina:scene"]))["camera"]["width"] == 16
