"""patina.batch.scheduler_address: a --scheduler address refused in one line, before any work,
for its form, its scheme, a port that stays silent and one that speaks something else."""

from __future__ import annotations

import contextlib
import os
import socket
import threading
import time

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patina.batch.scheduler_address import check_scheduler, probe_scheduler
from patina.cli import main
from repo_paths import ROOT


@contextlib.contextmanager
def server(answer: bytes):
    """A local port that accepts, sends `answer` (nothing: silent) and keeps the connection open."""
    listener = socket.create_server(("127.0.0.1", 0))
    held: list[socket.socket] = []

    def serve() -> None:
        with contextlib.suppress(OSError):
            while True:
                conn, _ = listener.accept()
                held.append(conn)
                conn.sendall(answer)

    threading.Thread(target=serve, daemon=True).start()
    try:
        yield f"tcp://127.0.0.1:{listener.getsockname()[1]}"
    finally:
        listener.close()
        for conn in held:
            conn.close()


@pytest.mark.parametrize(
    ("address", "message"),
    [
        ("ucx://127.0.0.1:8786", "ucx:// needs UCX"),
        ("inproc://127.0.0.1/1/2", "inproc:// a scheduler inside this process"),
        ("tls://127.0.0.1:8786", "tls:// needs certificates"),
        ("wss://127.0.0.1:8786", "wss:// needs certificates"),
        ("http://127.0.0.1:8786", "expected an address like tcp://host:8786"),
    ],
)
def test_other_schemes_are_one_line(address, message):
    """Before: ucx://, inproc://, tls:// ended in Dask's internal Python messages."""
    with pytest.raises(ValueError, match=f"^--scheduler {address}: {message}"):
        check_scheduler(address)


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=40))
def test_any_address_is_taken_or_refused_with_a_value_error(text):
    try:
        check_scheduler(text)
    except ValueError as e:
        assert str(e).startswith(f"--scheduler {text}: ") and "\n" not in str(e).replace(text, "")


def test_a_silent_port_is_reported_within_the_timeout():
    """Before: `render` and `batch` hung with no output."""
    with server(b"") as address:
        started = time.monotonic()
        with pytest.raises(ValueError, match=r"no Dask handshake within 0\.5 s"):
            probe_scheduler(address, timeout=0.5)
        assert time.monotonic() - started < 3


def test_a_port_speaking_something_else_is_reported_at_once(capsys, tmp_path):
    """Before: a 56-line traceback ending in "Unable to allocate 3.01 EiB"."""
    with server(b"HTTP/1.1 400 Bad Request\r\n\r\n") as address:
        with pytest.raises(ValueError, match=r"not a Dask scheduler \(it answered b'HTTP/1.1'"):
            probe_scheduler(address)
        ball = os.path.join(ROOT, "materials", "scenes", "preview-ball.json")
        assert main(["render", ball, "--scheduler", address, "--out", str(tmp_path / "a.png")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"patina: error: --scheduler {address}: not a Dask scheduler") and err.count("\n") == 1


def test_a_handshake_of_a_dask_size_passes():
    with server((24).to_bytes(8, "little") + bytes(24)) as address:
        probe_scheduler(address, timeout=2)
