"""A `--scheduler` address checked before any work: its form and scheme, then a handshake.

Only `tcp://HOST:PORT` is taken: `inproc://` names a scheduler inside this very process,
`ucx://` needs UCX and its Python bindings, `tls://` and `wss://` certificates that Patina
does not configure; each is refused with one line naming what to give instead. The address
is then tried with a timeout before Dask's client touches it: a Dask scheduler speaks first
on a new connection (its handshake: an 8-byte little-endian length, then that many bytes of
frames), so a port that accepts and stays silent is reported after CONNECT_TIMEOUT_S, and
one that answers other bytes (a web server, a database) is reported at once, where Dask's
client would take the first 8 bytes as a length and try to allocate exabytes.
"""

from __future__ import annotations

import socket
import struct
import time

IN_PROCESS = "in-process"  # --scheduler value: no Dask, the tasks one after the other here
CONNECT_TIMEOUT_S = 5  # an unreachable or silent scheduler is reported within seconds
MAX_HANDSHAKE_BYTES = 1 << 20  # a Dask handshake is some hundred bytes
OTHER_SCHEMES = {
    "inproc": "a scheduler inside this process, not one to connect to",
    "ucx": "needs UCX and ucx-py, which Patina does not install",
    "tls": "needs certificates (Dask security), which Patina does not configure",
    "ws": "Dask's websocket transport, which Patina does not use",
    "wss": "needs certificates (Dask security), which Patina does not configure",
}


def check_scheduler(scheduler: str | None) -> None:
    """An address's form checked before anything starts: tcp://HOST:PORT (or IN_PROCESS)."""
    if scheduler is None or scheduler == IN_PROCESS:
        return
    protocol, sep, rest = scheduler.partition("://")
    if sep and protocol in OTHER_SCHEMES:
        raise ValueError(f"--scheduler {scheduler}: {protocol}:// {OTHER_SCHEMES[protocol]}; give tcp://host:8786")
    host, colon, port = rest.rpartition(":")
    if not sep or protocol != "tcp" or not colon or not host:
        raise ValueError(f"--scheduler {scheduler}: expected an address like tcp://host:8786 (or {IN_PROCESS})")
    if not port.isdigit() or not 0 < int(port) < 65536:
        raise ValueError(f"--scheduler {scheduler}: the port must be a number in 1 .. 65535")


def _read(conn: socket.socket, count: int, deadline: float) -> bytes:
    data = b""
    while len(data) < count:
        conn.settimeout(max(deadline - time.monotonic(), 0.001))
        chunk = conn.recv(count - len(data))
        if not chunk:
            raise ConnectionError("it closed the connection")
        data += chunk
    return data


def probe_scheduler(scheduler: str, timeout: float = CONNECT_TIMEOUT_S) -> None:
    """ValueError (one line) unless a Dask scheduler answers at `scheduler` (checked by
    check_scheduler) within `timeout` seconds with a handshake of a sane size."""
    rest = scheduler.partition("://")[2]
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")  # an IPv6 address in brackets
    deadline = time.monotonic() + timeout
    try:
        with socket.create_connection((host, int(port)), timeout=timeout) as conn:
            head = _read(conn, 8, deadline)
            (size,) = struct.unpack("<Q", head)
            if not 0 < size <= MAX_HANDSHAKE_BYTES:
                raise ValueError(f"--scheduler {scheduler}: not a Dask scheduler (it answered {head!r}...)")
            _read(conn, size, deadline)
    except TimeoutError:
        raise ValueError(
            f"--scheduler {scheduler}: no Dask handshake within {timeout:g} s (a port that accepts but stays silent)"
        ) from None
    except OSError as e:
        raise ValueError(f"--scheduler {scheduler}: cannot connect: {e.strerror or e}") from None
