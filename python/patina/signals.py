"""Signals: a handler set for the length of a block, then put back (in the main thread only,
the one Python lets set handlers; elsewhere the block runs with the handlers as they are);
SIGTERM taken as Ctrl-C; both held from the worker processes a block starts."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
from multiprocessing import forkserver, resource_tracker
from typing import Any


@contextlib.contextmanager
def handling(signum: int, handler: Any) -> Iterator[None]:
    """`handler` (a function, signal.SIG_IGN, signal.default_int_handler) for `signum` meanwhile."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signum, handler)
    try:
        yield
    finally:
        signal.signal(signum, previous)


INTERRUPTS = (signal.SIGINT, signal.SIGTERM)  # Ctrl-C, and kill / a service manager / a batch system


@contextlib.contextmanager
def terminate_as_interrupt() -> Iterator[None]:
    """SIGTERM handled as Ctrl-C (KeyboardInterrupt) meanwhile: a command that keeps its work on
    Ctrl-C keeps it on `kill` too, and exits 130 instead of dying mid-write."""
    with handling(signal.SIGTERM, signal.default_int_handler):
        yield


@contextlib.contextmanager
def held_from_children() -> Iterator[None]:
    """For a block that starts worker processes (a Dask LocalCluster, asked to start them with
    `multiprocessing`'s "forkserver" method): they ignore SIGINT and SIGTERM, so that Ctrl-C at
    a terminal and `kill -- -PGID`, which reach the whole process group, are this process's to
    act on (a render finishes its first pass), not theirs. The fork server is started here
    with both ignored (a disposition inherited across exec and fork; Python keeps it), and the
    workers are forked from it. This process notes a signal that comes meanwhile and raises it
    as KeyboardInterrupt when the block ends (Ctrl-C while a cluster starts stops the command)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    came: list[int] = []
    # the resource tracker's start unblocks both signals in the starting thread: started first
    resource_tracker.ensure_running()
    # blocked while they are ignored, so one that comes is kept pending and noted below (a
    # thread of a library that does not block them would drop it: for the fork server's start,
    # a fraction of a second). A fork server started earlier, elsewhere, is used as it is.
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, INTERRUPTS)
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in INTERRUPTS}
    try:
        forkserver.ensure_running()
    finally:
        while signal.sigpending() & set(INTERRUPTS):
            came.append(signal.sigwait(INTERRUPTS))
        for s in INTERRUPTS:
            signal.signal(s, lambda signum, frame: came.append(signum))
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    if came:
        raise KeyboardInterrupt
