"""A signal's handler set for the length of a block, then put back: in the main thread only,
the one Python lets set handlers (elsewhere the block runs with the handlers as they are)."""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator
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
